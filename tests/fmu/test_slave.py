"""musclesim.fmu.slave: the base class's typed variables, its guards, its batched calls and FMU
state, and the contract the slaves' outputs are computed on demand by: `Slave.evaluate` sets the
outputs from the state, the inputs and the time, and changes nothing else, so that a slave may
evaluate when its outputs are read rather than after every step (and a master may read them any
number of times). Checked on every component as every shipped scenario drives it."""
import importlib
import pickle
import tomllib

import pytest

from musclesim.components import CATALOGUE
from musclesim.cosim import Master, load_scenario
from musclesim.fmu import Slave
from musclesim.fmu.slave import _NOT_STATE

from conftest import SCENARIOS

STEPS = 6


def _covering():
    """Shipped scenarios that together drive every component the scenarios use, each component
    in the first scenario (by name) that has it."""
    runs, seen = [], set()
    for path in sorted(SCENARIOS.glob("*.toml")):
        spec = tomllib.loads(path.read_text())
        used = {i.get("component") for i in spec.get("instances", {}).values()} - seen
        if "sweep" not in spec and used:
            runs.append(path)
            seen |= used
    return runs


def _classes():
    for name, where in CATALOGUE.items():
        module, cls = where.split(":")
        yield name, getattr(importlib.import_module(module), cls)


def _state(slave, outputs):
    """{attribute: its pickle} of everything but the outputs (functions, which cannot be
    pickled and which evaluate does not rebind, left out)."""
    state = {}
    for k, v in vars(slave).items():
        if k not in _NOT_STATE and k not in outputs:
            try:
                state[k] = pickle.dumps(v)
            except (pickle.PicklingError, AttributeError, TypeError):
                state[k] = id(v)
    return state


@pytest.fixture
def watched(monkeypatch):
    """Every slave's evaluate wrapped: {component: attributes it changed besides outputs}."""
    changed = {}
    for name, cls in _classes():
        def evaluate(self, _original=cls.evaluate, _name=name):
            outputs = {attr for vr, attr in enumerate(self._attrs)
                       if self.vars[vr].causality.name == "output"}
            outputs |= set(getattr(self, "buffers", ()))  # a kernel's inputs and outputs arrays
            before = _state(self, outputs)
            _original(self)
            after = _state(self, outputs)
            if after != before:
                changed.setdefault(_name, set()).update(
                    k for k in after.keys() | before.keys() if after.get(k) != before.get(k))
        monkeypatch.setattr(cls, "evaluate", evaluate)
    return changed


@pytest.mark.parametrize("path", _covering(), ids=lambda p: p.stem)
def test_evaluate_changes_nothing_but_the_outputs(fmu_dir, path, watched):
    s = load_scenario(path)
    res = Master(load_scenario(path, stop_time=STEPS * s.step), fmu_dir).run()
    assert res.error is None
    assert watched == {}


class Switched(Slave):
    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.parameter("n", 3, "1", "A count", type="Integer")
        self.parameter("on", 1.0, "1", "A switch", type="Boolean")
        self.output("state", "1", "On and counted", type="Boolean")
        self.output("count", "1", "Twice the count", type="Integer")

    def evaluate(self):
        self.state, self.count = self.on, 2 * self.n


def test_integer_and_boolean_variables_are_numbers_inside_and_typed_at_the_fmi_calls():
    slave = Switched(instance_name="s")
    kinds = {v.name: type(v).__name__ for v in slave.vars.values()}
    assert kinds == {"n": "Integer", "on": "Boolean", "state": "Boolean", "count": "Integer"}
    assert slave.vars[2].variability.name == "discrete"  # FMI 2.0 has no continuous Boolean
    slave.set_integer([0], [4])
    slave.set_boolean([1], [False])
    assert (slave.n, slave.on) == (4.0, 0.0)  # the physics reads numbers
    assert slave.get_integer([3]) == [8] and slave.get_boolean([2]) == [False]
    assert type(slave.get_integer([3])[0]) is int and type(slave.get_boolean([2])[0]) is bool
    slave.exit_initialization_mode()
    with pytest.raises(ValueError, match="parameter n is fixed"):
        slave.set_integer([0], [5])


def test_a_typed_declaration_must_hold_its_type():
    class Bad(Slave):
        def __init__(self, value, unit, **kwargs):
            super().__init__(**kwargs)
            self.parameter("n", value, unit, "A count", type="Integer")

    with pytest.raises(ValueError, match="variable n: 2.5 is not Integer"):
        Bad(2.5, "1", instance_name="b")
    with pytest.raises(ValueError, match="type 'Integer' is not Real, or Integer or Boolean of "
                                         "unit 1"):
        Bad(2, "m", instance_name="b")


class Lag(Slave):
    """A first-order lag y' = (u - y) / tau, u clamped to [0, 10], with a hidden state x (= y)
    and a pass-through output u_out = u (direct feedthrough)."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.parameter("tau", 0.5, "s", "Time constant", source="§two-mass")
        self.input("u", 1.0, "K", "Input temperature")
        self.output("y", "K", "Lagged temperature")
        self.output("u_out", "K", "The input, passed through", depends=("u",))
        self.x = 0.0

    def evaluate(self):
        self.y = self.x
        self.u_out = self.clamped_input("u", 0.0, 10.0, self.time)

    def advance(self, t, dt):
        self.x += dt * (self.clamped_input("u", 0.0, 10.0, t) - self.x) / self.tau


def test_a_step_advances_the_state_and_outputs_are_read_after_it():
    slave = Lag(instance_name="lag")
    slave.exit_initialization_mode()
    slave.do_step(0.0, 0.1)
    assert slave.time == 0.1 and slave.get_real([2, 3]) == [0.1 * 1.0 / 0.5, 1.0]
    assert slave.reader([2, 3])() == (0.2, 1.0) and slave.reader([2])() == (0.2,)
    slave.writer([1])([3.0])  # an input set between steps: the outputs follow it when read
    assert slave.get_real([3]) == [3.0]
    with pytest.raises(ValueError, match="writer.. sets inputs"):
        slave.writer([0, 1])
    with pytest.raises(ValueError, match="parameter tau is fixed"):
        slave.set_real([0], [1.0])


def test_an_input_out_of_range_is_clamped_and_warned_about_once_and_nan_refused():
    slave = Lag(instance_name="lag")
    slave.set_real([1], [12.0])
    slave.exit_initialization_mode()
    assert slave.get_real([3]) == [10.0]
    slave.do_step(0.0, 0.1)
    warned = [m.msg for m in slave.log_queue if "clamped" in m.msg]
    assert warned == ["u 12 at t = 0 s is outside [0, 10]; clamped to 10 (warned once)"]
    slave.set_real([1], [float("nan")])
    with pytest.raises(ValueError, match="input u is NaN at t = 0.1 s"):
        slave.get_real([3])


def test_a_warning_a_core_raises_goes_to_the_fmu_log():
    import warnings

    slave = Lag(instance_name="lag")

    def core(a, b):
        warnings.warn("out of its range")
        return a + b

    assert slave.logged(core, 1, 2) == 3
    assert [m.msg for m in slave.log_queue] == ["out of its range"]
    assert slave.log_queue[0].status.name == "warning" and slave.log_queue[0].debug is False


def test_a_saved_state_holds_the_hidden_state_and_restores_from_bytes_in_a_fresh_instance():
    slave = Lag(instance_name="lag")
    slave.exit_initialization_mode()
    slave.do_step(0.0, 0.1)
    data = Slave._fmu_state_to_bytes(slave._get_fmu_state())
    slave.do_step(0.1, 0.1)
    after = slave.get_real([2])
    other = Lag(instance_name="other")
    other._set_fmu_state(Slave._fmu_state_from_bytes(data))
    assert other.x == 0.2 and other.time == 0.1
    other.do_step(0.1, 0.1)
    assert other.get_real([2]) == after


def test_the_model_description_declares_feedthrough_initial_unknowns_and_units():
    root = Lag(instance_name="lag").to_xml()
    names = [v.get("name") for v in root.find("ModelVariables")]
    assert names == ["tau", "u", "y", "u_out"]
    outputs = root.find("ModelStructure/Outputs")
    assert [(u.get("index"), u.get("dependencies")) for u in outputs] == [("3", ""), ("4", "2")]
    assert [u.get("index") for u in root.find("ModelStructure/InitialUnknowns")] == ["3", "4"]
    units = {u.get("name"): u for u in root.find("UnitDefinitions")}
    assert set(units) == {"s", "K"} and units["K"].find("DisplayUnit").get("name") == "degC"
    tau = root.find("ModelVariables")[0]
    assert tau.get("description") == "Time constant (§two-mass)"


@pytest.mark.parametrize("declare", ["parameter", "input"])
def test_a_declaration_with_an_unknown_keyword_is_refused(declare):
    """`parameter` and `input` take `**role`: a keyword that is no role is an error, not
    ignored (python-control's habit for every function with **kwargs)."""
    class Wrong(Slave):
        def __init__(self, **kwargs):
            super().__init__(**kwargs)
            getattr(self, declare)("k", 1.0, "N/m", "Stiffness", bounds=(0.0, 1.0))

    with pytest.raises(TypeError, match="bounds"):
        Wrong(instance_name="w")
