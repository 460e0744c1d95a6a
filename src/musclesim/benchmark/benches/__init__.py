"""Benches written apart from the library's components, in other representations than theirs:
the blind benchmark's independent virtual hardware (sma: a wire on finite volumes with kinetic
hysteresis and its own controller; crawler: a pneumatic crawler with nozzle-law valves,
energy-balance chambers and LuGre friction)."""
