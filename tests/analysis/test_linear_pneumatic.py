"""musclesim.analysis.linear_pneumatic: the crawler's pressure loops (§crawler-hardware, §gait,
§valves): the identified plants against the ISO 6358 law by hand, the designed PIs, and the gain
and gait reference files the scenarios read (reproducible from a fresh design /
characterisation)."""
import math
import tomllib

import numpy as np
import pytest

from musclesim import cli
from musclesim.analysis import characterise, linear_pneumatic
from musclesim.cosim import Master, load_scenario
from musclesim.components.pneumatic.actuator import ActuatorParams
from musclesim.errors import UserError

from conftest import ROOT, SCENARIOS

IDENTIFICATION = SCENARIOS / "pneumatic-identification.toml"
PARAMS = SCENARIOS / "params"
PID_KEYS = {"Kp", "Ki", "Kd", "u_min", "u_max"}


@pytest.fixture(scope="module")
def report(fmu_dir):
    return linear_pneumatic.pneumatic(fmu_dir, {"scenario": str(IDENTIFICATION)})


def actuator_params(kind):
    """The SoftActuator parameters the identification scenario gives `kind`."""
    if kind == "central":
        return ActuatorParams()
    return ActuatorParams(**tomllib.loads((PARAMS / "extremal-actuator.toml").read_text()))


def hand_rates(params, p_op, volume):
    """(inflation, exhaust) pressure rates [Pa/s] at gauge p_op with a valve fully open, from the
    unchoked ISO 6358 law (§chamber) and dp/dt = kappa R T / V mdot at a constant volume."""
    p_atm, rho_0, R = 101325.0, 1.185, 287.05  # Pa; kg/m^3 (ISO 6358 reference); J/(kg K)

    def flow(p_up, p_down, C):  # absolute pressures; T = T_0 (the defaults)
        r = p_down / p_up
        assert r > params.b  # unchoked: the law below applies
        return C * p_up * rho_0 * math.sqrt(1.0 - ((r - params.b) / (1.0 - params.b)) ** 2)

    gain = params.kappa * R * params.T / volume
    chamber = p_op + p_atm
    return (gain * flow(params.p_supply + p_atm, chamber, params.C_in),
            gain * flow(chamber, params.p_exhaust + p_atm, params.C_out))


def test_identified_extremal_rate_matches_the_iso_6358_law_by_hand(report):
    p = actuator_params("extremal")
    # identified at full contact: V = V0 + dV_contact
    rate_in, rate_out = hand_rates(p, report["design"]["p_op"], p.V0 + p.dV_contact)
    fitted = report["loops"]["extremal"]["identified"]["rate_per_duty"]
    # the PRBS has as many up bits as down bits: the fit sits between the two rates (the PRBS
    # swings the pressure over a few kPa around p_op, so allow 10 %)
    assert 0.9 * min(rate_in, rate_out) <= fitted <= 1.1 * max(rate_in, rate_out)
    assert fitted == pytest.approx((rate_in + rate_out) / 2, rel=0.10)


def test_identified_central_rate_lies_between_held_and_quasi_static_blocks(report):
    """The central actuator is identified between its blocks, free to slide: its rate lies
    between that of the chamber alone at the elongated volume (blocks too slow to follow) and
    the quasi-static one, where the elongation s_a p / k follows the pressure and the
    chamber's compliance s_a^2 / k divides the rate by 1 + kappa p_abs s_a^2 / (k V)."""
    p, p_op = actuator_params("central"), report["design"]["p_op"]
    rate_in, rate_out = hand_rates(p, p_op, p.V0)
    assert (rate_in, rate_out) == pytest.approx((100.4e3, 92.6e3), rel=0.005)  # by hand
    k = load_scenario(IDENTIFICATION).instances["body"].parameters["k"]
    volume = p.V0 + p.s_a * p.s_a * p_op / k
    held = hand_rates(p, p_op, volume)
    quasi_static = [r / (1 + p.kappa * (p_op + 101325.0) * p.s_a ** 2 / (k * volume)) for r in held]
    fitted = report["loops"]["central"]["identified"]["rate_per_duty"]
    assert min(quasi_static) < fitted < max(held)


@pytest.mark.parametrize("kind", ["central", "extremal"])
def test_identified_around_the_operating_point(report, kind):
    lo, hi = report["loops"][kind]["identified"]["p_range"]
    assert lo < report["design"]["p_op"] < hi


@pytest.mark.parametrize("kind", ["central", "extremal"])
def test_designed_loops_margins_crossover_and_poles(report, kind):
    d, q = report["design"], report["loops"][kind]
    assert q["phase_margin_deg"] >= 45
    assert q["gain_margin"] is None or q["gain_margin"] > 2
    assert q["crossover"] == pytest.approx(d["crossover"], rel=0.1)
    assert 0 < q["closed_loop_pole_radius"] < 1
    # the same from the numbers alone, with the PI the PID FMU runs (u[k] = Kp e[k] + I[k],
    # I[k+1] = I[k] + Ki T e[k]): plant b z^-d / (z - a), PI (Kp z - Kp + Ki T) / (z - 1)
    fit, T = q["identified"], d["step"]
    a, b, delay = fit["a"], fit["b"], fit["delay_samples"]
    z = np.exp(1j * d["crossover"] * T)
    loop = (q["Kp"] * z - q["Kp"] + q["Ki"] * T) / (z - 1) * b / (z ** delay * (z - a))
    assert abs(loop) == pytest.approx(1.0, rel=1e-6)  # loop gain 1 at the design crossover
    assert math.degrees(np.angle(loop)) + 180 >= 45
    char = np.polyadd(np.polymul(np.polymul([1.0, -1.0], [1.0, -a]), [1.0] + [0.0] * delay),
                      [b * q["Kp"], b * (q["Ki"] * T - q["Kp"])])
    radius = np.abs(np.roots(char)).max()
    assert radius < 1
    # the report's margins and poles are of Kp + Ki T z / (z - 1) (an integrator one sample
    # ahead of the FMU's): the same to within a few 1e-5 here
    assert radius == pytest.approx(q["closed_loop_pole_radius"], abs=1e-3)


def test_cli_writes_pid_files_that_scenarios_read_and_match_the_committed_ones(
        fmu_dir, tmp_path, capsys, monkeypatch, report):
    monkeypatch.chdir(ROOT)  # the design's scenario path is relative to the project
    out = tmp_path / "gains"
    assert cli.main(["linear", "pneumatic", "--write", str(out), "--fmus", str(fmu_dir)]) == 0
    text, err = capsys.readouterr()
    assert "phase margin" in text and err.count("wrote the gains to") == 2
    for kind in ("central", "extremal"):
        fresh = tomllib.loads((out / f"pneumatic-{kind}-pid.toml").read_text())
        assert set(fresh) == PID_KEYS
        assert all(type(v) is float for v in fresh.values())
        assert (fresh["u_min"], fresh["u_max"], fresh["Kd"]) == (-1.0, 1.0, 0.0)
        assert fresh["Kp"] > 0 and fresh["Ki"] > 0
        assert fresh["Kp"] == pytest.approx(report["loops"][kind]["Kp"], rel=1e-9)
        # the committed gains are those of a fresh design (rerun the design when it changes), bit
        # for bit on any CPU: the identification's stick-slip run and its fit go through no BLAS
        committed = tomllib.loads((PARAMS / f"pneumatic-{kind}-pid.toml").read_text())
        assert committed == fresh, kind
    # a scenario reads them as a PID's parameters and runs
    lines = ['format = 2', 'step = 1e-3', 'stop_time = 0.01',
             'record = ["central.y", "extremal.y"]']
    for kind in ("central", "extremal"):
        lines += [f'[instances.{kind}]', 'component = "PID"',
                  f'parameters_file = "gains/pneumatic-{kind}-pid.toml"']
    (tmp_path / "pids.toml").write_text("\n".join(lines) + "\n")
    s = load_scenario(tmp_path / "pids.toml")
    assert s.instances["extremal"].parameters == fresh
    res = Master(s, fmu_dir).run()  # the FMU knows every key as a parameter
    assert res.error is None and len(res.time) == 11


def test_committed_gait_references_are_what_characterise_computes_now(fmu_dir, tmp_path, capsys):
    """The gait scenarios' references come from the characterisation run (~15 s), not typed in."""
    out = tmp_path / "refs.toml"
    code = cli.main(["characterise", str(SCENARIOS / "crawler-characterisation.toml"),
                     "--out", str(tmp_path / "char"), "--write", str(out), "--fmus", str(fmu_dir)])
    text, err = capsys.readouterr()
    assert code == 0, err
    assert "back extremal: firm ground contact from" in text and "wrote the gait references" in err
    fresh = tomllib.loads(out.read_text())
    committed = tomllib.loads((PARAMS / "crawler-gait-references.toml").read_text())
    assert set(fresh) == set(committed) == {"p_central", "p_anchor1", "p_anchor2"}
    # Bit for bit: the characterisation is a stick-slip run, where a last digit decides a stick
    # or a slip a step earlier and grows from there (1.3 % in p_central between OpenBLAS kernels
    # when the body's products went through BLAS); they are written out now, the same on any CPU.
    assert committed == fresh
    # plausibility: the blocks slide on their casings, so the elongation is the spring's
    # s_a p / k less a little friction lag (§two-mass, §friction)
    body = load_scenario(SCENARIOS / "crawler-pneumatic.toml").instances["body"].parameters
    stretch = ActuatorParams().s_a * fresh["p_central"] / body["k"]
    assert characterise.ELONGATION_TARGET < stretch < characterise.ELONGATION_TARGET * 1.05
    # firm contact needs the extremal pressure above the contact threshold for t_contact
    p_contact = actuator_params("extremal").p_contact
    for key in ("p_anchor1", "p_anchor2"):
        assert p_contact < fresh[key] / (1 + characterise.ANCHOR_MARGIN) < 1.1 * p_contact
