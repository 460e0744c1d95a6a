"""Co-simulated crawler scenarios against the monolithic numpy model of the same equations.

Topology of scenarios/crawler-ideal.toml::

    inputs --f_a--> body --v, f_n, N--> friction1 --f--> body
           --u1---------------------->  friction1
           --u2---------------------->  friction2 (like friction1, block 2)
"""
import dataclasses
import math

import numpy as np
import pytest

from musclesim.cosim import master, scenario, Signal
from musclesim.components.crawler import body, friction, inputs
from musclesim.components.crawler.monolithic import simulate_ideal

from conftest import ROOT, SCENARIOS

S = Signal.parse

IDEAL = SCENARIOS / "crawler-ideal.toml"


def cosim(fmu_dir, overrides=(), stop_time=None, algorithm=None):
    s = scenario.load(IDEAL, overrides, stop_time)
    if algorithm:
        s = dataclasses.replace(s, algorithm=algorithm)
    res = master.Master(s, fmu_dir).run()
    assert res.error is None
    return res


def assert_matches(res, times, states, tol=1e-9):
    np.testing.assert_array_equal(res.time, times)
    for col, i in (("body.flange_a.s", 0), ("body.flange_a.v", 1), ("body.flange_b.s", 2),
                   ("body.flange_b.v", 3)):
        scale = max(1.0, np.abs(states[:, i]).max())
        np.testing.assert_allclose(res[S(col)], states[:, i], rtol=0, atol=tol * scale, err_msg=col)


def test_nominal_scenario_equals_monolithic_model(fmu_dir):
    res = cosim(fmu_dir)
    assert_matches(res, *simulate_ideal())
    # the crawler moves forward at 1 Hz, phi = 1.64 rad (§ideal-actuation)
    assert res[S("body.x_cm")][-1] > 1.0


def test_gauss_seidel_feeds_the_body_the_stepped_source(fmu_dir):
    """Gauss-Seidel steps the signal source first, so the body sees f_a(t + h) in its step."""
    res = cosim(fmu_dir, stop_time=5.0, algorithm="gauss-seidel")
    assert_matches(res, *simulate_ideal(stop_time=5.0, actuator_lead=True))
    jacobi = cosim(fmu_dir, stop_time=5.0)
    assert not np.array_equal(res[S("body.flange_a.s")], jacobi[S("body.flange_a.s")])


def test_incline_effects_and_parameters_reach_the_fmus(fmu_dir):
    theta = math.radians(7.5)
    overrides = [f"body.theta={theta!r}", "friction1.t_switch=0.2", "friction2.t_switch=0.3",
                 "friction2.mu_s_high=0.8", "inputs.phi=4.0", "body.m1=0.25",
                 "body.k_slope=0.01", "body.c_ground=0.4"]
    res = cosim(fmu_dir, overrides, stop_time=5.0)
    ref = simulate_ideal(body_p=body.BodyParams(theta=theta, m1=0.25, k_slope=0.01, c_ground=0.4),
                         friction_p=(friction.FrictionParams(t_switch=0.2),
                                     friction.FrictionParams(t_switch=0.3, mu_s_high=0.8)),
                         inputs_p=inputs.InputParams(phi=4.0), stop_time=5.0)
    assert_matches(res, *ref)


def test_rows_belong_to_their_time_stamp(fmu_dir):
    """Row k holds inputs, states and the friction evaluated from them, all at t_k."""
    res = cosim(fmu_dir, stop_time=0.05)
    p, fp, ip = body.BodyParams(), friction.FrictionParams(), inputs.InputParams()
    for k in (0, 17, 50):
        t = res.time[k]
        f_a, u1, _ = inputs.signals(t, ip)
        assert res[S("inputs.f_a")][k] == f_a and res[S("inputs.u1")][k] == u1
        x = [res[S("body.flange_a.s")][k], res[S("body.flange_a.v")][k],
             res[S("body.flange_b.s")][k], res[S("body.flange_b.v")][k]]
        f_n1, _ = body.nonfriction_forces(x, f_a, p)
        mu_s, mu_k = friction.coefficients(u1, fp)
        expected = friction.friction_force(x[1], f_n1, body.normal_forces(p)[0], mu_s, mu_k, fp.v_s)
        assert res[S("friction1.flange.f")][k] == expected


def test_reference_result_is_reproduced(fmu_dir):
    """The co-simulation still gives the reference result kept next to the components, bit for
    bit: no product in the body goes through BLAS, whose kernel (chosen per CPU) would round
    differently (17 significant digits in the file are every bit of a float)."""
    ref = np.loadtxt(ROOT / "components" / "crawler" / "reference.csv", delimiter=",", skiprows=1)
    res = cosim(fmu_dir, stop_time=5.0)
    np.testing.assert_array_equal(res.time[::10], ref[:, 0])
    for col, i in (("body.flange_a.s", 1), ("body.flange_a.v", 2), ("body.flange_b.s", 3),
                   ("body.flange_b.v", 4)):
        np.testing.assert_array_equal(res[S(col)][::10], ref[:, i], err_msg=col)


def test_runs_leave_no_fmu_copy_of_musclesim_on_sys_path(fmu_dir):
    """pythonfmu prepends each FMU's resources; left there, child processes import the FMU's
    copy."""
    import sys
    from pathlib import Path

    cosim(fmu_dir, stop_time=0.01)
    assert not [p for p in sys.path if (Path(p) / "slavemodule.txt").is_file()]


def test_direction_minus_one_is_the_mirror_image(fmu_dir):
    """Swapping the indicators (and so the blocks' roles) mirrors the motion exactly:
    x1 -> -x2, x2 -> -x1; crawler-ideal-backward's metrics count along its travel."""
    fwd = cosim(fmu_dir, stop_time=3.0)
    back = master.Master(scenario.load(SCENARIOS / "crawler-ideal-backward.toml", (), 3.0),
                         fmu_dir).run()
    assert back.error is None
    np.testing.assert_allclose(back[S("body.flange_a.s")], -fwd[S("body.flange_b.s")], rtol=0, atol=1e-12)
    np.testing.assert_allclose(back[S("body.flange_b.s")], -fwd[S("body.flange_a.s")], rtol=0, atol=1e-12)
    assert fwd[S("body.x_cm")][-1] > 0.1
    from musclesim.cosim import results
    s = scenario.load(SCENARIOS / "crawler-ideal-backward.toml", (), 3.0)
    m_back = results.compute_metrics(back, s.metrics)
    m_fwd = results.compute_metrics(fwd, scenario.load(IDEAL, (), 3.0).metrics)
    for name in ("mean_speed", "stride_length"):
        assert m_back[name] == pytest.approx(m_fwd[name], rel=1e-9) and m_back[name] > 0
    with pytest.raises(ValueError, match="direction must be 1 or -1"):
        inputs.InputParams(direction=0.5).check()
