"""The component catalogue: every FMU musclesim builds, by name, with the slave class behind it.

Each subsystem folder holds pure physics cores (no FMI), thin FMU slaves (`slaves.py`) and a
README saying where the equations are: the model reference in docs/model (§model-reference).
`declarations` gives what a component declares of each variable (its unit, default, type,
source and role for the diagnosis), read from the slave class without building an FMU. The format
migration table, `RENAMED` and `renamed` (the new name of a port renamed in format 2, which
messages give), lives in `migration` and is importable from here.
"""
from __future__ import annotations

import importlib
from functools import cache

from musclesim.components.migration import RENAMED, renamed
from musclesim.fmu import Declaration

__all__ = ["CATALOGUE", "RENAMED", "declarations", "renamed"]

# component name -> "module:class" of its FMU slave (the FMU file is fmus/<name>.fmu)
CATALOGUE: dict[str, str] = {
    "CrawlerBody": "musclesim.components.crawler.slaves:CrawlerBody",
    "FrictionBlock": "musclesim.components.crawler.slaves:FrictionBlock",
    "FrictionSwitchingInputs": "musclesim.components.crawler.slaves:FrictionSwitchingInputs",
    "GaitSequencer": "musclesim.components.crawler.slaves:GaitSequencer",
    "PID": "musclesim.components.control.slaves:PID",
    "GainScheduledPID": "musclesim.components.control.slaves:GainScheduledPID",
    "BangBang": "musclesim.components.control.slaves:BangBang",
    "Thermocouple": "musclesim.components.sensors.slaves:Thermocouple",
    "LoadCell": "musclesim.components.sensors.slaves:LoadCell",
    "LaserSensor": "musclesim.components.sensors.slaves:LaserSensor",
    "PressureSensor": "musclesim.components.sensors.slaves:PressureSensor",
    "SmaWire": "musclesim.components.sma.slaves:SmaWire",
    "CapstanMultiplier": "musclesim.components.multiplier.slaves:CapstanMultiplier",
    "PreisachInverse": "musclesim.components.sma.slaves:PreisachInverse",
    "BiasSpring": "musclesim.components.loads.slaves:BiasSpring",
    "DeadWeight": "musclesim.components.loads.slaves:DeadWeight",
    "Electromagnet": "musclesim.components.loads.slaves:Electromagnet",
    "SoftActuator": "musclesim.components.pneumatic.slaves:SoftActuator",
    "SignalSource": "musclesim.components.sources.slaves:SignalSource",
    "ForcReference": "musclesim.components.sources.slaves:ForcReference",
    "StrainProfile": "musclesim.components.sources.slaves:StrainProfile",
    "LoadingProfile": "musclesim.components.sources.slaves:LoadingProfile",
    "BendingActuator": "musclesim.components.bending.slaves:BendingActuator",
    "QuadrupedBody": "musclesim.components.quadruped.slaves:QuadrupedBody",
    "LegSequencer": "musclesim.components.quadruped.slaves:LegSequencer",
}


@cache
def declarations(component: str) -> dict[str, Declaration]:
    """{variable name: `musclesim.fmu.Declaration`} of the component named `component` (a key of
    `CATALOGUE`)."""
    module, cls = CATALOGUE[component].split(":")
    return getattr(importlib.import_module(module), cls).declarations()
