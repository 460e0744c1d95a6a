"""Pneumatic soft actuators of the crawler: chamber, PWM valves, pumps (SPEC.md 1.1, 1.5, 5)."""
