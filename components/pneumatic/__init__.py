"""Pneumatic soft actuators of the crawler: chamber, PWM valves, pumps (§crawler-hardware, §gait,
§chamber)."""

__all__ = ["actuator"]
