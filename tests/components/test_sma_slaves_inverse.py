"""The PreisachInverse FMU slave (§preisach-inverse) in-process: its T_ref is the inverse core
stepped by hand, bit for bit; stress-aware and stress-ignored modes; parameter errors; the round
trip through the forward model."""
import math

import numpy as np
import pytest

from musclesim.components.sma import datasets
from musclesim.components.sma.inverse import PreisachInverse as InverseCore
from musclesim.components.sma.preisach import PreisachModel
from musclesim.components.sma.profiles import loading_profile, strain_profile
from musclesim.components.sma.slaves import PreisachInverse

from conftest import in_process

ZERO_C = 273.15
RATE = 25.0  # Hz, as tests/components/test_inverse.py: the 550 s profiles keep their shape
TIMES = np.arange(0.0, 550.0, 1 / RATE)
DT = 1 / RATE


def _inverse(**params):
    return in_process(PreisachInverse, "inverse", **params)


def start(slave, eps0, sigma0):
    """Initialization with the inputs of the first sample; returns the value references."""
    vr = {v.name: v.value_reference for v in slave.vars.values()}
    slave.enter_initialization_mode()
    slave.set_real([vr["eps_ref"], vr["sigma_ref"]], [eps0, sigma0])
    slave.exit_initialization_mode()
    return vr


def drive(slave, vr, eps_r, sigma, k0=0):
    """Samples k0, k0 + 1, ...: inputs set, T_ref read, step taken. Returns T_ref [K]."""
    inputs, out = [vr["eps_ref"], vr["sigma_ref"]], [vr["T_ref"]]
    T = []
    for k, (e, s) in enumerate(zip(eps_r.tolist(), sigma.tolist()), start=k0):
        slave.set_real(inputs, [e, s])
        T.append(slave.get_real(out)[0])
        slave.do_step(k * DT, DT)
    return np.array(T)


def run(eps_r, sigma, **params):
    """The whole run through the slave's FMI calls: T_ref [K] at every sample."""
    slave = _inverse(**params)
    return drive(slave, start(slave, eps_r[0], sigma[0]), eps_r, sigma)


def by_hand(eps_r, sigma, hysteresis=0.0, sigma_surface=0.0):
    """The inverse core stepped sample by sample: reset, then step."""
    core = InverseCore(datasets.surface(hysteresis, sigma_surface))
    T = [core.reset(eps_r[0], sigma[0])]
    T += [core.step(e, s) for e, s in zip(eps_r[1:].tolist(), sigma[1:].tolist())]
    return np.array(T) + ZERO_C


def rmse_percent(eps, eps_r):
    return 100 * math.sqrt(np.mean((eps - eps_r) ** 2)) / eps_r.max()


@pytest.mark.parametrize("hysteresis, sigma_surface", [(0.0, 0.0), (1.0, 0.0), (1.0, 125e6)],
                         ids=["wire-aware", "set1-aware", "set1-ignored"])
def test_t_ref_is_the_core_stepped_by_hand(hysteresis, sigma_surface):
    eps_r, sigma = strain_profile("SP IV")(TIMES[:3000]), loading_profile("LP V")(TIMES[:3000])
    T = run(eps_r, sigma, hysteresis=hysteresis, sigma_surface=sigma_surface)
    assert np.array_equal(T, by_hand(eps_r, sigma, hysteresis, sigma_surface))


def test_t_ref_is_direct_feedthrough_of_both_inputs():
    # the output of t_k follows the inputs of t_k: declared, so a master orders the exchange
    root = _inverse().to_xml()
    index = {v.get("name"): str(i) for i, v in enumerate(root.find("ModelVariables"), start=1)}
    (unknown,) = root.find("ModelStructure/Outputs")
    assert unknown.get("index") == index["T_ref"]
    assert unknown.get("dependencies").split() == [index["eps_ref"], index["sigma_ref"]]
    slave = _inverse(hysteresis=1.0)
    vr = start(slave, 0.0, 125e6)
    slave.set_real([vr["eps_ref"]], [0.02])  # no step: the output moves with its input
    assert slave.get_real([vr["T_ref"]])[0] > 40.0 + ZERO_C


def test_variables_and_units():
    variables = {v.name: v for v in _inverse().vars.values()}
    assert {n: v.causality.name for n, v in variables.items()} == {
        "hysteresis": "parameter", "sigma_surface": "parameter", "eps_ref": "input",
        "sigma_ref": "input", "T_ref": "output"}
    slave = _inverse()
    assert {n: slave._meta[n].unit for n in variables} == {
        "hysteresis": "1", "sigma_surface": "Pa", "eps_ref": "1", "sigma_ref": "Pa", "T_ref": "K"}


def test_fmu_state_restores_the_memory():
    eps_r, sigma = strain_profile("SP II")(TIMES[:2000]), loading_profile("LP V")(TIMES[:2000])
    slave = _inverse(hysteresis=1.0)
    vr = start(slave, eps_r[0], sigma[0])
    drive(slave, vr, eps_r[:1500], sigma[:1500])
    assert len(slave.core.extrema) == 8  # nested minor loops: a memory worth restoring
    state = slave._get_fmu_state()
    ahead = drive(slave, vr, eps_r[1500:], sigma[1500:], k0=1500)
    slave._set_fmu_state(state)
    assert state["core"].bases is slave.core.bases  # shared, not copied
    assert np.array_equal(drive(slave, vr, eps_r[1500:], sigma[1500:], k0=1500), ahead)


# --- stress-aware and stress-ignored -------------------------------------------------------

def test_stress_ignored_output_does_not_see_the_stress():
    eps_r = strain_profile("SP I")(TIMES[:2000])
    lo, hi = np.full_like(eps_r, 105e6), loading_profile("LP I")(TIMES[:2000])
    ignored = [run(eps_r, s, hysteresis=1.0, sigma_surface=125e6) for s in (lo, hi)]
    assert np.array_equal(*ignored)
    aware = [run(eps_r, s, hysteresis=1.0) for s in (lo, hi)]
    assert np.abs(aware[0] - aware[1]).max() > 1.0  # K


def test_single_surface_equals_the_aware_inverse_at_its_stress_level():
    """Data set 1 has a level at 125 MPa: the stress-aware inverse interpolates its tables with
    weight 0 there, and at_stress(125 MPa) returns that level's F, so both inverses read the same
    table entries: equal to round-off (observed: exactly)."""
    eps_r, sigma = strain_profile("SP IV")(TIMES), np.full_like(TIMES, 125e6)
    aware = run(eps_r, sigma, hysteresis=1.0)
    ignored = run(eps_r, sigma, hysteresis=1.0, sigma_surface=125e6)
    assert np.abs(aware - ignored).max() <= 1e-9


def test_single_surface_and_aware_inverse_between_stress_levels():
    """Data set 0 has levels at 120 and 130 MPa: at 125 MPa the single surface interpolates F,
    the aware inverse the inverse temperatures (§preisach-inverse), which differ where F saturates
    (several K for the same strain). Compared where it matters, in strain through the forward
    model: both within the bases' error between levels (0.6 % of the maximum strain,
    tests/components/test_inverse.py::test_bases_invert_the_surface) of each other."""
    eps_r, sigma = strain_profile("SP II")(TIMES), np.full_like(TIMES, 125e6)
    strains = []
    for sigma_surface in (0.0, 125e6):
        T = run(eps_r, sigma, sigma_surface=sigma_surface)
        strains.append(forward(T, sigma, datasets.surface(0)))
    assert np.abs(strains[0] - strains[1]).max() < 0.006 * eps_r.max()


# --- errors --------------------------------------------------------------------------------

@pytest.mark.parametrize("params, match", [
    ({"hysteresis": 1.0, "sigma_surface": 150e6},
     r"sigma_surface must be 0 .*\[1\.05e\+08, 1\.45e\+08\] Pa \(got 1\.5e\+08\)"),
    ({"sigma_surface": 50e6}, r"sigma_surface must be 0 .*\[6e\+07, 2e\+08\] Pa"),
    ({"sigma_surface": -1e6}, r"sigma_surface must be 0 "),
    ({"hysteresis": 7.0}, r"hysteresis = 7 is no data set"),
], ids=["above-set-1", "below-wire", "negative", "unknown-set"])
def test_bad_parameters_name_themselves(params, match):
    with pytest.raises(ValueError, match=match):
        _inverse(**params).exit_initialization_mode()


@pytest.mark.parametrize("name", ["eps_ref", "sigma_ref"])
def test_non_finite_input_is_an_error_naming_it(name):
    slave = _inverse(hysteresis=1.0)
    vr = start(slave, 0.01, 125e6)
    slave.do_step(0.0, DT)
    slave.set_real([vr[name]], [math.nan])
    with pytest.raises(ValueError, match=rf"input {name} is nan at t = 0\.04 s"):
        slave.get_real([vr["T_ref"]])
    with pytest.raises(ValueError, match=rf"input {name} is nan at t = 0\.04 s"):
        slave.do_step(DT, DT)


def test_out_of_range_inputs_are_clamped_with_one_warning_in_the_log():
    slave = _inverse(hysteresis=1.0)
    vr = start(slave, 0.01, 125e6)
    for e, s in ((0.05, 200e6), (0.06, 300e6)):
        slave.set_real([vr["eps_ref"], vr["sigma_ref"]], [e, s])
        assert slave.get_real([vr["T_ref"]])[0] == 130.0 + ZERO_C
        slave.do_step(0.0, DT)
    messages = sorted(m.msg for m in slave.log_queue)
    assert len(messages) == 2
    assert messages[0].startswith("reference strain 0.05 at t = 0 s is outside")
    assert messages[1].startswith("stress 2e+08 Pa at t = 0 s is outside")


# --- round trip ----------------------------------------------------------------------------

def forward(T_ref, sigma, surface):
    """Strain of the forward model driven by T_ref [K] at the stress sigma."""
    model = PreisachModel(surface)
    return np.array([model.step(T - ZERO_C, s) for T, s in zip(T_ref.tolist(), sigma.tolist())])


@pytest.mark.parametrize("hysteresis", [0.0, 1.0, 2.0])
@pytest.mark.parametrize("sp", ["SP I", "SP IV"])
def test_round_trip_at_constant_stress(sp, hysteresis):
    """T_ref through the forward model gives back eps_r within the inverse's claims
    (tests/components/test_inverse.py): RMSE < 1 % of the maximum strain, and everywhere within
    the bases' inversion error between stress levels (0.6 %; data set 0 has no level at
    125 MPa)."""
    eps_r, sigma = strain_profile(sp)(TIMES), np.full_like(TIMES, 125e6)
    eps = forward(run(eps_r, sigma, hysteresis=hysteresis), sigma, datasets.surface(hysteresis))
    assert rmse_percent(eps, eps_r) < 1.0
    assert np.abs(eps - eps_r).max() < 0.006 * eps_r.max()


@pytest.mark.parametrize("lp", ["LP I", "LP V"])
@pytest.mark.parametrize("hysteresis", [0.0, 1.0])
def test_round_trip_under_time_varying_stress(hysteresis, lp):
    """Stress-aware: T_ref only moves the way eps_r does (§position-control's direction, where the
    stress alone would push it back it holds, tests/components/test_inverse.py), and the wire it
    drives tracks several times better than with the single 125 MPa surface (§position-control's
    comparison)."""
    eps_r, sigma = strain_profile("SP IV")(TIMES), loading_profile(lp)(TIMES)
    T_ref = run(eps_r, sigma, hysteresis=hysteresis)
    assert np.all(np.diff(T_ref) * np.diff(eps_r) >= 0.0)
    ignored = run(eps_r, sigma, hysteresis=hysteresis, sigma_surface=125e6)
    surface = datasets.surface(hysteresis)
    aware_error = rmse_percent(forward(T_ref, sigma, surface), eps_r)
    assert 3 * aware_error < rmse_percent(forward(ignored, sigma, surface), eps_r)


@pytest.mark.parametrize("hysteresis, sigma_surface", [(0.0, 0.0), (1.0, 125e6)],
                         ids=["wire-aware", "set1-ignored"])
def test_kernel_paths_agree(hysteresis, sigma_surface):
    """The PreisachInverse's compiled kernel gives the bits of its plain-Python source along the
    reference profiles."""
    from kernel_paths import assert_paths_agree
    eps_r, sigma = strain_profile("SP IV")(TIMES[:1500]), loading_profile("LP V")(TIMES[:1500])

    def inputs(k):
        return {"eps_ref": float(eps_r[k]), "sigma_ref": float(sigma[k])}
    assert_paths_agree(_inverse(hysteresis=hysteresis, sigma_surface=sigma_surface), inputs, DT,
                       1500)
