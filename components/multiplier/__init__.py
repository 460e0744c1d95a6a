"""Fast actuation from minor loops (SPEC.md 3.1): the capstan multiplier, a long SMA wire folded
over fixed capstans into segments, each with its own temperature, stress and hysteresis memory."""

__all__ = ["capstan"]
