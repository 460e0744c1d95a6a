"""What ships inside every FMU: the project's pythonfmu base class `Slave`, the SI `UNITS` it
declares, `experiment`, a component's default experiment, `step_end`, the clock every slave
keeps, and `declare`, one declaration of a core's parameter (its unit, description, source,
role: an effect's bounds or a `Calibration`, and its `Plausible` values, by default its unit's in
`PLAUSIBLE`, `DIFFERENCES` for a difference, with the `SLIPS` a value is likely written in) that
the slave, the docs, the diagnosis and the scenario checks read.

Modules: `slave` (the base class), `kernel` (`KernelSlave`, a slave whose physics is a compiled
`Kernel`), `compiled` (`jit`: numba where installed, plain Python where not), `declaration` (a
parameter's one declaration), `units` (the units a variable may carry), `clock` (the default
experiment and the step's end) and `fmi3` (the FMI 3.0 face of every slave, in FMI 3.0 FMUs
only).

`musclesim build` copies this package into each FMU's resources, so it imports nothing but the
standard library, numpy and pythonfmu: an FMU must run where only Python, numpy and scipy are
installed.
"""
from musclesim.fmu.declaration import Calibration, Declaration, PlausibleSpec, declare
from musclesim.fmu.clock import experiment, step_end
from musclesim.fmu.compiled import CACHE, COMPILED, jit, parallel_jit, range_over_cases
from musclesim.fmu.kernel import Kernel, KernelSlave, no_state
from musclesim.fmu.slave import Slave
from musclesim.fmu.units import (CELSIUS, DIFFERENCES, PLAUSIBLE, QUANTITIES, SLIPS, UNITS,
                                 Plausible)

__all__ = ["Slave", "UNITS", "experiment", "step_end", "declare", "Calibration", "Declaration",
           "Kernel", "KernelSlave", "no_state", "jit", "parallel_jit", "range_over_cases", "COMPILED",
           "CACHE", "PlausibleSpec", "Plausible", "PLAUSIBLE", "DIFFERENCES", "QUANTITIES",
           "SLIPS", "CELSIUS"]
