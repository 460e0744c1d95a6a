"""Signal sources: references and loads as FMUs (constant, sine, square, triangle)."""

__all__ = ["forc", "signals"]
