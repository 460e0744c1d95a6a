"""How the component tests drive a component: an FMU through FMPy (`run_fmu`), a wire-like slave
in this process (`run_wire`, `heat_cool`), a slave past initialization (`started`, `set_reals`),
the bending actuator's core (`make_bending`)."""
import math
from types import SimpleNamespace

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from musclesim.components.bending import actuator, beam
from musclesim.components.sma.reference_wire import load_params
from musclesim.cosim import host

from conftest import in_process

DT = 1e-3  # s, the wire tests' step
OUTPUTS = ("T", "strain", "flange_s", "stress", "R", "P")  # a wire's outputs
AREA = math.pi * 25e-6 ** 2  # m2, the 50 um wire of the bending actuator


def run_fmu(fmu_dir, name, inputs, dt=1e-3, params=None, outputs=("flange.f",), log=None, init=None):
    """Run FMU `name` with inputs {name: values per point t_0..t_n} (value k set at t_k, held
    over step k; `init` {name: value} overrides the values set while initializing); returns
    {output: array at t_0..t_n}, the FMU's log in `log`."""
    path = fmu_dir / f"{name}.fmu"
    md = read_model_description(str(path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    n = len(next(iter(inputs.values())))
    slave = FMU2Slave(guid=md.guid, unzipDirectory=extract(path), instanceName=name,
                      modelIdentifier=md.coSimulation.modelIdentifier)
    key = id(slave)
    host.LOG_SINKS[key] = {name: SimpleNamespace(log=log if log is not None else [])}
    try:
        slave.instantiate(callbacks=host.callbacks(key), loggingOn=True)
        slave.setupExperiment(startTime=0.0)
        for par, value in (params or {}).items():
            slave.setReal([vr[par]], [value])
        ins, outs = [vr[k] for k in inputs], [vr[k] for k in outputs]
        slave.enterInitializationMode()
        start = {k: v[0] for k, v in inputs.items()} | (init or {})
        slave.setReal(ins, [float(v) for v in start.values()])
        slave.exitInitializationMode()
        rows = []
        for k in range(n):
            slave.setReal(ins, [float(v[k]) for v in inputs.values()])
            rows.append(slave.getReal(outs))
            if k < n - 1:
                slave.doStep(k * dt, dt)
        slave.terminate()
        slave.freeInstance()
    finally:
        del host.LOG_SINKS[key]
    return dict(zip(outputs, np.array(rows).T))


def run_wire(slave, u, f, T_amb=293.15, dt=DT, names=OUTPUTS):
    """Step an in-process slave with u[k], f[k] held over step k; {name: array at t_0..t_n}."""
    slave.u, slave.flange_f, slave.T_amb = u[0], f[0], T_amb
    slave.enter_initialization_mode()
    slave.exit_initialization_mode()
    slave.get_real([])
    rows = [[getattr(slave, n) for n in names]]
    for k in range(len(u)):
        slave.u, slave.flange_f = u[k], f[k]
        slave.set_real([], [])  # inputs changed: outputs are evaluated again
        slave.get_real([])
        slave.do_step(k * dt, dt)
        rows.append([getattr(slave, n) for n in names])
    return dict(zip(names, np.array(rows).T))


def heat_cool(volts, on=0.6, total=3.0, dt=DT):
    """`volts` for the first `on` of `total` seconds, then none, at steps `dt`."""
    n = round(total / dt)
    return np.where(np.arange(n) < round(on / dt), volts, 0.0)


def started(cls, **params):
    """An in-process slave past initialization, and its value references by name."""
    slave = in_process(cls, "slave", **params)
    slave.enter_initialization_mode()
    slave.exit_initialization_mode()
    return slave, {v.name: v.value_reference for v in slave.vars.values()}


def set_reals(slave, vr, values):
    """Set the inputs `values` {name: value} of `slave` (value references `vr`)."""
    slave.set_real([vr[name] for name in values], list(values.values()))


def make_bending(beam_p=None, layout=None):
    """A BendingActuator core of `beam_p` and `layout` (defaults: the study's), its wires' surface
    at the pretension."""
    layout = layout or actuator.WireLayout()
    surface = actuator.hysteresis_surface(load_params(), layout.pretension / AREA)
    return actuator.BendingActuator(beam_p or beam.BeamParams(), layout,
                                    actuator.wire_thermal(layout.length), surface)
