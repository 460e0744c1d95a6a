"""The master's economies (ordered exchange, batched calls, inputs set only when needed) change no
result: it agrees to the bit with a naive master that sets every input through fmpy's high-level
calls and settles feedthrough by repeated sweeps instead of ordering."""
import dataclasses

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from musclesim.cosim import Signal, scenario
from musclesim.errors import UserError
from musclesim.cosim.master import Master

from conftest import SCENARIOS

S = Signal.parse


def naive_run(s, fmu_dir, tmp_path, step_order):
    slaves, refs = {}, {}
    for name, inst in s.instances.items():
        path = fmu_dir / f"{inst.component}.fmu"
        md = read_model_description(str(path))
        refs[name] = {v.name: v.valueReference for v in md.modelVariables}
        slave = FMU2Slave(guid=md.guid, unzipDirectory=extract(path, tmp_path / name),
                          modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
        slave.instantiate()
        slave.setupExperiment(startTime=s.start_time)
        for par, value in inst.parameters.items():
            slave.setReal([refs[name][par]], [value])
        slaves[name] = slave

    def get(signal):
        return slaves[signal.instance].getReal([refs[signal.instance][signal.variable]])[0]

    def settle():  # as many sweeps over all connections as there are instances
        for _ in s.instances:
            for src, dst in s.connections:
                inst, var = dst.instance, dst.variable
                slaves[inst].setReal([refs[inst][var]], [get(src)])

    for slave in slaves.values():
        slave.enterInitializationMode()
    settle()
    for slave in slaves.values():
        slave.exitInitializationMode()
    settle()
    t, rows = s.start_time, []
    for k in range(s.n_steps + 1):
        rows.append([get(c) for c in s.record])
        if k == s.n_steps:
            break
        for name in step_order:
            if s.algorithm == "gauss-seidel":
                for src, dst in s.connections:
                    inst, var = dst.instance, dst.variable
                    if inst == name:
                        slaves[inst].setReal([refs[inst][var]], [get(src)])
            slaves[name].doStep(t, s.step)
        t = s.start_time + (k + 1) * s.step  # t0 + k h, as FMPy counts its points
        settle()
    for slave in slaves.values():
        slave.terminate()
        slave.freeInstance()
    return np.array(rows)


@pytest.mark.parametrize("algorithm", ["jacobi", "gauss-seidel"])
def test_master_equals_naive_master(fmu_dir, tmp_path, algorithm):
    s = scenario.load(SCENARIOS / "crawler-ideal.toml", ["friction1.t_switch=0.1"], stop_time=1.0)
    s = dataclasses.replace(s, algorithm=algorithm)
    master = Master(s, fmu_dir)
    res = master.run()
    assert res.error is None
    expected = naive_run(s, fmu_dir, tmp_path, master.step_order)
    np.testing.assert_array_equal(res.data[:, :len(s.record)], expected)


def _drop(s, instances, replayed):
    """`s` without `instances` and without the connections into `replayed` inputs."""
    return dataclasses.replace(
        s, instances={n: i for n, i in s.instances.items() if n not in instances},
        connections=tuple((a, b) for a, b in s.connections if b not in replayed
                          and not {a.instance, b.instance} & set(instances)),
        record=tuple(c for c in s.record if c.instance not in instances),
        metrics={}, plots=())


def test_replayed_inputs_reproduce_the_closed_loop_bit_for_bit(fmu_dir):
    """The diagnosis's isolation: the wire and thermocouple re-simulated with the controller's
    recorded voltage replayed are the closed loop exactly (Jacobi: inputs at t_k, held)."""
    s = scenario.load(SCENARIOS / "sma-bench-tracking.toml", stop_time=6.0)
    loop = Master(s, fmu_dir).run()
    alone = _drop(s, {"pid", "reference"}, {S("wire.u")})
    res = Master(alone, fmu_dir, {S("wire.u"): loop[S("pid.y")]}).run()
    assert res.error is None
    for c in res.names:
        assert np.array_equal(res[c], loop[c]), c


def test_an_unconnected_input_holds_the_value_a_scenario_sets(fmu_dir, tmp_path):
    """A bench condition (issue 20 item 1): the ambient temperature, an input nothing feeds, set
    like a parameter. With no heating the wire relaxes from T_init to it, as the lumped thermal
    model (§sma-wire) says; the same input connected or replayed cannot also be set."""
    path = tmp_path / "wire.toml"
    path.write_text('step = 0.01\nstop_time = 30.0\nrecord = ["wire.T"]\n'
                    '[instances.wire]\ncomponent = "SmaWire"\n'
                    'parameters = { T_init = 293.15, T_amb = 313.15 }\n')
    warm = Master(scenario.load(path), fmu_dir).run()
    assert warm.error is None
    assert np.all(np.diff(warm[S("wire.T")]) > 0) and warm[S("wire.T")][-1] == pytest.approx(313.15,
                                                                                      abs=0.05)
    still = Master(scenario.load(path, ["wire.T_amb=293.15"]), fmu_dir).run()
    assert np.all(still[S("wire.T")] == 293.15)  # at its own ambient the wire does not move
    replayed = {S("wire.T_amb"): np.full(3001, 300.0)}
    with pytest.raises(UserError, match="wire.T_amb is an input replayed from data"):
        Master(scenario.load(path), fmu_dir, replayed)


def test_integer_and_boolean_values_are_checked_and_move_on_both_hosts(fmu_dir, tmp_path):
    """A Boolean parameter takes 0 or 1, an Integer a whole number; a Boolean output is not
    connected to a Real input; recorded Integer and Boolean outputs are the same numbers whoever
    hosts the FMU (fmpy reads them through fmi2GetInteger and fmi2GetBoolean)."""
    path = tmp_path / "relay.toml"
    path.write_text(
        'format = 2\nstep = 0.01\nstop_time = 2.0\n'
        'record = ["relay.on", "gait.stride", "relay.y"]\n'
        'connections = [["wire.T", "relay.T"]]\n'
        '[instances.wire]\ncomponent = "SmaWire"\nparameters = { drive_current = 1.0 }\n'
        '[instances.relay]\ncomponent = "BangBang"\n'
        'parameters = { T_on = 290.0, T_off = 300.0, initially_on = 0.0 }\n'
        '[instances.gait]\ncomponent = "GaitSequencer"\n'
        'parameters = { t_protrusion = 0.2, t_stance = 0.3 }\n')
    runs = [Master(scenario.load(path), fmu_dir, host=h).run() for h in ("direct", "fmpy")]
    assert np.array_equal(runs[0].data, runs[1].data)
    assert set(runs[0][S("relay.on")]) == {0.0} and runs[0][S("gait.stride")][-1] > 2
    with pytest.raises(UserError) as err:
        Master(scenario.load(path, ["relay.initially_on=0.5", "gait.direction=1.5"]), fmu_dir)
    message = str(err.value)
    assert "relay.initially_on is a Boolean: 0.5 is neither 0 (false) nor 1 (true)" in message
    assert "gait.direction is an Integer: 1.5 is not a whole number" in message
    wrong = path.read_text().replace('[["wire.T", "relay.T"]]',
                                     '[["wire.T", "relay.T"], ["relay.on", "wire.u"]]')
    path.write_text(wrong)
    with pytest.raises(UserError, match="connection relay.on -> wire.u joins a Boolean output to "
                                        "a Real input; FMI connects variables of one type"):
        Master(scenario.load(path), fmu_dir)
