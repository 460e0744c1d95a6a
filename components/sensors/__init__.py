"""Sensors with their imperfections as parameters, off by default (§sma-bench, §named-effects)."""

__all__ = ["sensor"]
