"""Loads of the SMA wire on the position-control bench (§sma-bench, §position-control, §loads)."""

__all__ = ["loads"]
