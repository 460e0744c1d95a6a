"""The contract the slaves' outputs are computed on demand by: `Slave.evaluate` sets the outputs
from the state, the inputs and the time, and changes nothing else, so that a slave may evaluate
when its outputs are read rather than after every step (and a master may read them any number
of times). Checked on every component as every shipped scenario drives it."""
import importlib
import pickle
import tomllib

import pytest

from musclesim.components import CATALOGUE
from musclesim.cosim import Master, load_scenario
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
