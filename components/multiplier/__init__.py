"""Fast actuation from minor loops (§capstan-multiplier): the capstan multiplier, a long SMA wire
folded over fixed capstans into segments, each with its own temperature, stress and hysteresis
memory."""

__all__ = ["capstan"]
