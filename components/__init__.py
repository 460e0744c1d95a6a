"""The component catalogue: every FMU musclesim builds, by name, with the slave class behind it.

Each subsystem folder holds pure physics cores (no FMI), thin FMU slaves (`slaves.py`) and a
README saying where the equations are: the model reference in docs/model (§model-reference).
`declarations` gives what a component declares of each variable (its unit, default, type,
source and role for the diagnosis), read from the slave class without building an FMU; `renamed`
the new name of a port renamed in format 2 (`RENAMED`), which messages give.
"""
import importlib
from functools import cache

# component name -> "module:class" of its FMU slave (the FMU file is fmus/<name>.fmu)
CATALOGUE = {
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

# {component: {old name: new}}: ports renamed to the Modelica Standard Library's names in scenario
# and data-set format 2 (an old name ending in "." renames every variable under it), which a
# master names when a file uses the old name. An old name that names another variable now (the
# PID's y) is refused in a file that does not declare format 2.
RENAMED = {"CrawlerBody": {"flange1.": "flange_a.", "flange2.": "flange_b."},
           "PID": {"r": "u_s", "y": "u_m", "u": "y"},
           "GainScheduledPID": {"r": "u_s", "y": "u_m", "u": "y"},
           "BangBang": {"u": "y"}}


def renamed(component, variable):
    """The name `variable` of `component` has had since format 2 renamed it, or None."""
    for old, new in RENAMED.get(component, {}).items():
        if variable == old or old.endswith(".") and variable.startswith(old):
            return new + variable[len(old):]
    return None


@cache
def declarations(component):
    """{variable name: `musclesim.fmu.Declaration`} of the component named `component`."""
    module, cls = CATALOGUE[component].split(":")
    return getattr(importlib.import_module(module), cls).declarations()
