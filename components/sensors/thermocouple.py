"""Thermocouple: first-order lag, bias, seeded noise and quantisation (§sma-bench), all off by
default.

The junction follows the wire with time constant tau (contact and coat, §sma-bench: a bare single
thermocouple gave 6-8 C RMS error); the reading adds a bias and Gaussian noise and is rounded to
the quantisation step. The generic scalar-sensor core in `sensor` does it; kept under this name.
"""
from musclesim.components.sensors.sensor import SensorParams, lag_weights, make_rng, noise_sample, reading

__all__ = ["SensorParams", "lag_weights", "make_rng", "noise_sample", "reading"]
