"""musclesim.fmu.declaration: one declaration per parameter (`musclesim.fmu.declare`): the slave,
its FMU's model description and the diagnosis's catalogues read what a core's dataclass declares,
and nothing else."""
import dataclasses

import pytest
from fmpy import read_model_description

from musclesim.components import CATALOGUE, declarations
from musclesim.diagnosis import EFFECTS
from musclesim.diagnosis.effects import CALIBRATION
from musclesim.fmu import Calibration, Slave, declare


@dataclasses.dataclass(frozen=True)
class Core:
    m: float = declare(0.2, "kg", "Block mass", source="§two-mass")
    k: float = declare(100.0, "N/m", "Stiffness", calibrate=Calibration(0.5, 2.0, True, "soft"))
    c: float = declare(0.0, "N.s/m", "Effect, 0 = off: drag", effect=(0.0, 5.0))
    plain: float = 1.0  # no declaration: not a parameter of the FMU


class Component(Slave):
    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.parameters_of(Core, skip=("m",),
                           overrides={"k": {"default": 150.0, "source": "§ideal-actuation"}})
        self.input("x", 0.0, "m", "Position", calibrate=Calibration(-1.0, 1.0, False, "offset"))


def test_a_slave_declares_a_cores_fields_with_their_roles_and_its_overrides():
    d = Component.declarations()
    assert list(d) == ["k", "c", "x"]  # m skipped, plain undeclared
    assert (d["k"].default, d["k"].unit, d["k"].source) == (150.0, "N/m", "§ideal-actuation")
    assert d["k"].calibrate == Calibration(0.5, 2.0, True, "soft")
    assert d["c"].effect == (0.0, 5.0) and d["c"].calibrate is None
    assert d["x"].causality == "input" and d["x"].calibrate.why == "offset"
    slave = Component(instance_name="c")
    # the FMU's description names the section the value comes from
    assert slave.vars[0].description == "Stiffness (§ideal-actuation)"
    assert slave.k == 150.0


def test_an_override_of_a_field_the_core_does_not_declare_is_refused():
    class Wrong(Slave):
        def __init__(self, **kwargs):
            super().__init__(**kwargs)
            self.parameters_of(Core, overrides={"mass": {"default": 1.0}})

    with pytest.raises(ValueError, match="Core declares no mass"):
        Wrong(instance_name="w")
    with pytest.raises(ValueError, match="unit 'furlong'"):
        declare(1.0, "furlong", "a length")


def test_every_declared_role_is_in_the_diagnosis_catalogues_and_only_those():
    """An effect parameter a component declares belongs to an effect of the library, and every
    effect parameter the library names is declared with its bounds around its default (off); the
    calibration catalogue is exactly the declared calibrations."""
    named = {(e.component, n) for e in EFFECTS for n in e.names}
    declared_effects, declared_calibrations = set(), set()
    for component in CATALOGUE:
        for d in declarations(component).values():
            if d.effect:
                declared_effects.add((component, d.name))
                assert d.effect[0] <= d.default <= d.effect[1], (component, d.name)
            if d.calibrate:
                declared_calibrations.add((component, d.name))
                assert d.calibrate.lower < d.calibrate.upper, (component, d.name)
    assert declared_effects == named
    assert {(c.component, c.name) for c in CALIBRATION} == declared_calibrations


@pytest.mark.parametrize("component", sorted(CATALOGUE))
def test_the_fmus_model_description_is_the_declaration(fmu_dir, component):
    md = read_model_description(str(fmu_dir / f"{component}.fmu"))
    declared = declarations(component)
    for v in md.modelVariables:
        d = declared[v.name]
        assert (v.causality, v.unit or "1") == (d.causality, d.unit), v.name
        assert v.description == (f"{d.description} ({d.source})" if d.source
                                 else d.description), v.name
        assert v.type == d.type, v.name
        if v.causality in ("parameter", "input"):
            start = {"Real": float, "Integer": int, "Boolean": lambda x: x == "true"}[v.type]
            assert start(v.start) == d.default, v.name
    assert [v.name for v in md.modelVariables] == list(declared)
