"""The sources' FMUs (components/sources/slaves.py): each output is its core's value at the
slave's clock, stepped as a master steps it; bad profile parameters are named."""
import pytest

from musclesim.components.sma import profiles
from musclesim.components.sources import forc, signals
from musclesim.components.sources.slaves import (AREA_127UM, ForcReference, LoadingProfile,
                                                 SignalSource, StrainProfile)

from conftest import in_process


def outputs(slave, names, steps, dt):
    """[(time, outputs)] at every communication point, as a master reads them."""
    slave.enter_initialization_mode()
    slave.exit_initialization_mode()
    out = []
    for k in range(steps):
        slave.get_real([])
        out.append((slave.time, tuple(getattr(slave, n) for n in names)))
        slave.do_step(slave.time, dt)
    return out


def test_signal_source_is_the_wave_at_its_clock():
    params = {"kind": 2.0, "offset": 1.0, "amplitude": 0.5, "frequency": 2.0, "t_start": 0.1}
    p = signals.SignalParams(**params)
    for t, (y,) in outputs(in_process(SignalSource, "src", **params), ["y"], 500, 1e-3):
        assert y == signals.value(t, p)
    with pytest.raises(ValueError, match="kind must be one of"):
        in_process(SignalSource, "src", kind=9.0).setup()


def test_forc_reference_gives_the_run_and_its_phase():
    p = forc.ForcParams(period=4.0)
    seen = outputs(in_process(ForcReference, "forc", period=4.0), ["T_ref", "run", "phase"],
                   2000, 0.05)
    for t, (T, run, phase) in seen:
        assert (T, run, phase) == forc.value(t, p)
    assert {run for _, (_, run, _) in seen} == set(range(21)) | {-1.0}


def test_profiles_are_the_shipped_generators():
    strain = outputs(in_process(StrainProfile, "sp", profile=2.0), ["eps_ref"], 300, 0.1)
    sp = profiles.strain_profile("SP II")
    assert all(eps == sp(t) for t, (eps,) in strain)
    load = outputs(in_process(LoadingProfile, "lp", profile=5.0, seed=3.0),
                   ["sigma_ref", "f_ref"], 300, 0.1)
    lp = profiles.loading_profile("LP V", seed=3)
    assert all(s == lp(t) and f == s * AREA_127UM for t, (s, f) in load)


@pytest.mark.parametrize("params, match", [({"profile": 5.0}, "profile must be one of 1..4"),
                                           ({"profile": 1.5}, "profile must be one of"),
                                           ({"lo": 0.05}, "lo <= hi"),
                                           ({"duration": 0.0}, "duration > 0")])
def test_bad_profile_parameters_are_named(params, match):
    with pytest.raises(ValueError, match=match):
        in_process(StrainProfile, "sp", **params).setup()


@pytest.mark.parametrize("cls, params", [
    (SignalSource, {"kind": 1.0, "offset": 1.0, "amplitude": 0.5, "frequency": 2.0,
                    "phase": 0.3, "t_start": 0.1}),
    (SignalSource, {"kind": 2.0, "offset": 1.0, "amplitude": 0.5, "frequency": 7.0,
                    "duty": 0.3}),
    (SignalSource, {"kind": 3.0, "amplitude": 2.0, "frequency": 3.0}),
    (SignalSource, {"kind": 4.0, "amplitude": 2.0, "frequency": 0.5}),
    (ForcReference, {"period": 0.5}),
    *[(StrainProfile, {"profile": float(k), "duration": 30.0}) for k in range(1, 5)],
    *[(LoadingProfile, {"profile": float(k), "duration": 30.0}) for k in range(1, 7)]])
def test_the_compiled_kernel_is_its_python_bit_for_bit(cls, params):
    """Each source's compiled kernel gives the bits of its plain-Python source along a run."""
    from kernel_paths import assert_paths_agree

    assert_paths_agree(in_process(cls, "src", **params), lambda k: None, 0.0137, 2500)
