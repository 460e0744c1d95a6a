"""What ships inside every FMU: the project's pythonfmu base class `Slave`, the SI `UNITS` it
declares, `experiment`, a component's default experiment, `step_end`, the clock every slave
keeps, and `declare`, one declaration of a core's parameter (its unit, description, source and
role: an effect's bounds or a `Calibration`) that the slave, the docs and the diagnosis read.

`musclesim build` copies this package into each FMU's resources, so it imports nothing but the
standard library, numpy and pythonfmu: an FMU must run where only Python, numpy and scipy are
installed.
"""
from musclesim.fmu.slave import (UNITS, Calibration, Declaration, Slave, declare, experiment,
                                 step_end)

__all__ = ["Slave", "UNITS", "experiment", "step_end", "declare", "Calibration", "Declaration"]
