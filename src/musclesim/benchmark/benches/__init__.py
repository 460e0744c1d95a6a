"""Benches written apart from the library's components, in other representations than theirs:
the blind benchmark's independent virtual hardware (sma: a wire on finite volumes with kinetic
hysteresis and its own controller, hysteresis in sma_kinetics; crawler: a pneumatic crawler whose
friction, valves, spools, chambers, contact and camera each come in several forms, the air's
laws in crawler_air). The families of bench forms (`musclesim.benchmark.family`,
`musclesim.benchmark.family_crawler`) draw those forms per case."""
