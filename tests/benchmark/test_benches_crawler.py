"""The independent crawler bench of the blind benchmark: its valve, spool, chamber, contact and
friction laws in each of their forms against hand-derived cases, the camera's, the gait it walks,
its hidden effects, its default forms pinned to the sealed runs' bits, independence from the
library (musclesim.benchmark.benches.crawler and crawler_air; its cases: test_plan.py)."""
import ast
import hashlib
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from musclesim.benchmark.benches import crawler as ic
from musclesim.benchmark.benches import crawler_air as air

ROOT = Path(__file__).resolve().parents[2]
NOMINAL = ic.Crawler()  # the model's values, ideal sensors
# every hidden effect and imperfect sensor at once (the digest test's second bench)
HIDDEN = ic.Crawler(leak=8.4e-11, open_delay=0.004, close_delay=0.002, pump_reserve=1.5,
                    surface_change=(1.5, 0.7), sensor_tau=0.01, sensor_noise=30.0,
                    sensor_quantum=10.0, video_delay=0.05, video_noise=2e-4, video_quantum=5e-4,
                    k3=400.0, stiffening=0.2, bending=0.2, decay=0.3, decay_time=2.0, bulge=1e-6,
                    seed=7)


@pytest.fixture(scope="module")
def walk():
    """6 s of the nominal bench: two strides."""
    return ic.run(NOMINAL, 6.0)


def test_nozzle_flow_choked_laminar_and_continuous():
    kappa, R, T = air.KAPPA, air.R_AIR, 293.15
    choked = 2.5e-7 * 300e3 * math.sqrt(kappa / (R * T)) * (2 / (kappa + 1)) ** (
        (kappa + 1) / (2 * (kappa - 1)))  # the textbook choked flow
    assert air.nozzle_flow(300e3, 100e3, 2.5e-7, T) == pytest.approx(choked, rel=1e-12)
    at_critical = air.nozzle_flow(100e3, 100e3 * air.R_CRIT, 2.5e-7, T)
    assert air.nozzle_flow(100e3, 100e3 * air.R_CRIT * 1.0001, 2.5e-7, T) == pytest.approx(
        at_critical, rel=1e-6)  # subsonic meets choked at the critical ratio
    edge = air.nozzle_flow(100e3, 99.9e3, 2.5e-7, T)
    assert air.nozzle_flow(100e3, 99.90001e3, 2.5e-7, T) == pytest.approx(edge, rel=1e-3)
    assert air.nozzle_flow(100e3, 99.95e3, 2.5e-7, T) == pytest.approx(edge / 2, rel=1e-9)
    assert air.nozzle_flow(100e3, 100e3, 2.5e-7, T) == 0.0
    assert air.nozzle_flow(100e3, 120e3, 2.5e-7, T) == 0.0


def test_pwm_open_share_and_delays():
    period = 0.02
    for duty in (0.1, 0.37, 0.9):  # over whole periods the share is the duty, whatever the phase
        assert ic.open_share(0.0, 0.2, duty, period, 0.3, 0.0, 0.0) == pytest.approx(duty)
    # delays shift the window's edges: open [5, 8) ms of each period with duty 0.25, 5 and 3 ms
    assert ic.open_share(0.0, 0.02, 0.25, period, 0.0, 0.005, 0.003) == pytest.approx(0.15)
    assert ic.open_share(0.004, 0.005, 0.25, period, 0.0, 0.005, 0.003) == 0.0
    assert ic.open_share(0.006, 0.007, 0.25, period, 0.0, 0.005, 0.003) == 1.0
    assert ic.open_share(0.0, 0.02, 0.1, period, 0.0, 0.005, 0.001) == 0.0  # closes before open


def test_a_closed_chamber_compressed_relaxes_from_adiabatic_to_isothermal():
    ch = air.Chamber(1e-5, ic.air_settings(replace(NOMINAL, tau_wall=0.5)))
    ch.step(1e-5, 0.0, 0.0, ic.P_ATM, 0.9e-5)  # a fast 10 % squeeze
    assert ch.p == pytest.approx(ic.P_ATM * (1 / 0.9) ** air.KAPPA, rel=2e-3)
    for _ in range(5000):  # 5 s, ten wall time constants
        ch.step(1e-3, 0.0, 0.0, ic.P_ATM, 0.9e-5)
    assert ch.p == pytest.approx(ic.P_ATM / 0.9, rel=1e-4)
    assert ch.T == pytest.approx(ic.T_ROOM, abs=1e-3)


def test_lugre_block_sticks_below_the_static_force_and_slides_above():
    normal, mu_s, mu_k, dt, m = 2.0, 1.0, 0.75, 2e-4, 0.2
    # reached over 0.5 s, then held 0.5 s; between the kinetic and the static force LuGre's
    # breakaway depends on the force's rate (Canudas de Wit et al. 1995), so not tested there
    for push, sticks in ((1.4, True), (2.1, False)):
        block, x, v = ic.FRICTIONS["lugre"](), 0.0, 0.0
        for i in range(5000):
            f = block.force(v, normal, mu_s, mu_k, 0.0, NOMINAL, dt)
            v += (push * min(i / 2500, 1.0) + f) / m * dt
            x += v * dt
        if sticks:  # presliding only: about the bristles' deflection push / sigma0
            assert abs(x) < 2 * push / (NOMINAL.bristle * normal) and abs(v) < 1e-4
        else:  # broken away: kinetic friction, (push - mu_k N) / m over most of the hold
            assert v > 0.6 * (push - mu_k * normal) / m * 0.5


def test_gait_phases():
    assert ic.gait(0.0) == (ic.P_ANCHOR, 0.0, 0.0)
    assert ic.gait(1.0) == (ic.P_ANCHOR, ic.P_CENTRAL, 0.0)
    assert ic.gait(2.0) == (ic.P_ANCHOR, ic.P_CENTRAL, ic.P_ANCHOR)
    assert ic.gait(2.9) == ic.gait(5.9) == (0.0, 0.0, ic.P_ANCHOR)


def test_the_bench_climbs_with_its_pressures_tracking_the_gait(walk):
    t, p, x = walk["time"], walk["p_true"], walk["x_true"]
    i = np.searchsorted(t, 1.7)  # the end of phase 2: back and central at their references
    assert np.allclose(p[i], [ic.P_ANCHOR, ic.P_CENTRAL, 0.0], atol=500.0)
    assert np.max(p[np.searchsorted(t, 1.8):np.searchsorted(t, 2.4), 2]) > ic.P_ANCHOR  # anchored
    gain = (x[-1] - x[np.searchsorted(t, 3.0)]).mean()  # one stride, climbing
    assert 0.01 < gain < 0.04  # §gait's real strides are 0.022-0.028 m on the flat
    assert np.max(np.abs(walk["x"] - x)) < 1e-3  # 30 frames/s interpolated: within a mm
    assert np.all(np.abs(walk["duty"]) <= 1.0)


def test_hidden_effects_act_as_named(walk):
    t = walk["time"]
    late = ic.run(replace(NOMINAL, open_delay=0.015, close_delay=0.005), 1.0)
    j = np.searchsorted(t, 0.1)
    assert late["p_true"][j, 0] < walk["p_true"][j, 0]  # the back inflates later
    leaky = ic.run(replace(NOMINAL, leak=8.4e-11), 6.0)
    k = np.searchsorted(t, 2.3)
    assert np.mean(np.abs(leaky["duty"][k - 500:k, 0])) > 2 * np.mean(
        np.abs(walk["duty"][k - 500:k, 0]))  # the PI keeps feeding a leak
    sag = ic.run(replace(NOMINAL, pump_reserve=1.0), 1.0)
    assert sag["p_true"][j, 0] < walk["p_true"][j, 0]
    stiff = ic.run(replace(NOMINAL, stiffening=0.35), 2.0)
    k = np.searchsorted(t, 1.7)
    assert np.diff(stiff["x_true"][k]) < np.diff(walk["x_true"][k])  # stretches less
    scaled = ic.run(replace(NOMINAL, video_scale=1.05), 6.0)
    assert np.allclose(scaled["x"], 1.05 * walk["x"], atol=1e-12)
    for slick in (replace(NOMINAL, bending=0.45), replace(NOMINAL, decay=0.4, decay_time=3.0),
                  replace(NOMINAL, surface_change=(0.5, 0.6))):
        out = ic.run(slick, 6.0)  # less grip: the anchors slip, the robot climbs less
        assert out["x_true"][-1].mean() < walk["x_true"][-1].mean() - 2e-3


def test_the_crawler_bench_imports_nothing_of_the_library():
    for name in ("crawler.py", "crawler_air.py"):  # numpy and scipy only, and each other
        tree = ast.parse((ROOT / "src/musclesim/benchmark/benches" / name).read_text())
        modules = [a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names]
        modules += [n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)]
        assert not [m for m in modules if m.startswith("musclesim")
                    and m != "musclesim.benchmark.benches.crawler_air"]


def digest(out):
    """sha256 of a run's arrays, keys in order."""
    h = hashlib.sha256()
    for key in sorted(out):
        h.update(key.encode())
        h.update(out[key].tobytes())
    return h.hexdigest()


@pytest.mark.parametrize("bench, expected", [
    (NOMINAL, "14f71f42769db135056c182bf8b3051a98dd743186a22c8bb813d48b4a54a7f0"),
    (HIDDEN, "2b2daba5acf6b135ca3c432c350e625e44444626fb95340e922e8d029abd4149"),
], ids=["nominal", "hidden-effects"])
def test_the_default_forms_keep_the_sealed_benches_bit_for_bit(bench, expected):
    # digests computed at e7fdd5c, before the benches had forms (issue 57): the blind
    # benchmark's sealed results were drawn from these runs
    assert digest(ic.run(bench, 3.0)) == expected


FORM_CASES = [pytest.param({name: form}, id=f"{name}={form}")
              for name, forms in ic.FORMS.items() for form in forms[1:]]
FORM_CASES += [pytest.param({"k3": 2000.0}, id="spring=stiffening"),
               pytest.param({"valve_law": "iso6358", "valve_b": 0.5}, id="valve_b=0.5"),
               pytest.param({"video_fps": 60.0}, id="video_fps=60"),
               pytest.param({"video_hold": True}, id="video_hold")]


@pytest.fixture(scope="module")
def second():
    """1 s of the nominal bench: the back anchored, the central actuator inflating."""
    return ic.run(NOMINAL, 1.0)


@pytest.mark.parametrize("fields", FORM_CASES)
def test_every_form_runs_and_changes_what_the_bench_records(fields, second):
    out = ic.run(replace(NOMINAL, **fields), 1.0)
    assert all(np.all(np.isfinite(a)) for a in out.values())
    assert np.all(np.abs(out["duty"]) <= 1.0)
    assert any(not np.array_equal(out[k], second[k]) for k in ("duty", "p_meas", "x"))
    assert 0.5 * ic.P_ANCHOR < out["p_true"][-1, 0] < 1.5 * ic.P_ANCHOR  # the back still anchors


@pytest.mark.parametrize("name", list(ic.FORMS))
def test_an_unknown_form_is_refused_with_the_allowed_ones(name):
    with pytest.raises(ValueError, match=f"Crawler.{name} = 'none'.*{', '.join(ic.FORMS[name])}"):
        replace(NOMINAL, **{name: "none"})


def test_iso6358_chokes_as_the_nozzle_and_the_orifice_follows_bernoulli():
    T, area = 293.15, 2.5e-7
    for b in (0.2, 0.3, 0.5):  # choked (r = 0.18 below b and R_CRIT): the same flow
        assert air.iso6358_flow(550e3, 100e3, area, T, b) == pytest.approx(
            air.nozzle_flow(550e3, 100e3, area, T), rel=1e-12)
    # subsonic the shapes differ: at r = 0.7 the ellipse of b = 0.3 against the nozzle's
    r, b = 0.7, 0.3
    choked = air.nozzle_flow(300e3, 90e3, area, T)
    assert air.iso6358_flow(100e3 / r, 100e3, area, T, b) == pytest.approx(
        choked / 3 / r * math.sqrt(1 - ((r - b) / (1 - b)) ** 2), rel=1e-12)
    assert air.iso6358_flow(100e3 / r, 100e3, area, T, b) != pytest.approx(
        air.nozzle_flow(100e3 / r, 100e3, area, T), rel=0.02)
    rho = 101e3 / (air.R_AIR * T)  # the upstream air's density
    assert air.orifice_flow(101e3, 100e3, area, T) == pytest.approx(
        area * math.sqrt(2 * rho * 1e3), rel=1e-12)
    assert air.orifice_flow(400e3, 100e3, area, T) > 1.5 * air.nozzle_flow(400e3, 100e3, area, T)
    for law in (air.orifice_flow, air.iso6358_flow):  # continuous at the laminar edge, zero back
        edge = law(100e3, 99.9e3, area, T)
        assert law(100e3, 99.90001e3, area, T) == pytest.approx(edge, rel=1e-3)
        assert law(100e3, 99.95e3, area, T) == pytest.approx(edge / 2, rel=1e-9)
        assert law(100e3, 100e3, area, T) == law(100e3, 120e3, area, T) == 0.0


def test_isothermal_and_polytropic_chambers_keep_their_laws():
    V0, dt = 1e-5, 1e-4
    for form, n in (("isothermal", 1.0), ("polytropic", 1.3)):
        ch = air.Chamber(V0, ic.air_settings(replace(NOMINAL, chamber=form, polytropic_n=n)))
        mass = ic.P_ATM * V0 / (air.R_AIR * ic.T_ROOM)
        invariant = ic.P_ATM * V0 ** n / mass ** n
        for i in range(200):  # 10 ms filling, then 10 ms squeezed by 10 % without flow
            V = V0 * (1 - 0.1 * max(i - 100, 0) / 100)
            mass += dt * ch.step(dt, 1.0 if i < 100 else 0.0, 0.0, 2 * ic.P_ATM, V)
            assert ch.p * V ** n / mass ** n == pytest.approx(invariant, rel=1e-9)
        assert ch.p > 1.1 * ic.P_ATM  # filled and squeezed
        if form == "isothermal":
            assert ch.T == ic.T_ROOM and ch.p * V / mass == pytest.approx(air.R_AIR * ic.T_ROOM)
        else:  # the temperature follows the law: (p / p_atm) ** ((n - 1) / n) of the room's
            assert ch.T == pytest.approx(ic.T_ROOM * (ch.p / ic.P_ATM) ** ((n - 1) / n))


def test_spools_lag_ring_and_wait_as_their_forms_say():
    tau, dt = 0.002, 1e-5
    second, dead = air.SecondOrder(tau, 0.7), air.DeadTime(tau)
    peak, opening = 0.0, []
    for _ in range(2000):  # 20 ms of a step to fully open
        second.advance(1.0, dt)
        peak = max(peak, second.x)
        opening.append(dead.advance(1.0, dt))
    zeta = 0.7  # the step's overshoot of a damped oscillator
    assert peak == pytest.approx(1 + math.exp(-zeta * math.pi / math.sqrt(1 - zeta ** 2)),
                                 rel=1e-3)
    # settled within its envelope exp(-zeta t / tau), the opening clipped at full
    assert second.advance(1.0, dt) == pytest.approx(1.0, abs=2 * math.exp(-zeta * 0.02 / tau))
    fresh = air.SecondOrder(tau, zeta)
    assert max(fresh.advance(1.0, dt) for _ in range(1000)) == 1.0  # over the peak, 8.8 ms
    t = dt * np.arange(1, 2001)  # the coil: nothing for tau / 2, then a lag of tau / 2
    expected = np.where(t <= tau / 2, 0.0, 1 - np.exp(-(t - tau / 2) / (tau / 2)))
    assert np.allclose(opening, expected, atol=dt / (tau / 2))


def test_contact_forms_about_the_threshold():
    share = {form: [ic._contact(replace(NOMINAL, contact=form), p, 8e3)
                    for p in (4e3, 7.9e3, 8.1e3, 9.5e3, 12e3)] for form in ic.FORMS["contact"]}
    assert share["threshold"] == [0.0, 0.0, 1.0, 1.0, 1.0]
    assert share["bulging"] == pytest.approx([0.0, 0.5 - 0.1 / 6, 0.5 + 0.1 / 6, 0.75, 1.0])
    assert share["logistic"][2] == pytest.approx(1 / (1 + math.exp(-0.1)))


def test_dahl_friction_under_a_long_slide_tends_to_the_kinetic_force():
    normal, mu_k, v, dt = 2.0, 0.75, 0.01, 2e-4
    block = ic.FRICTIONS["dahl"]()
    forces = [block.force(v, normal, 1.0, mu_k, 0.0, NOMINAL, dt) for _ in range(500)]
    assert forces[0] > -0.9 * mu_k * normal  # the bristles build up over their length
    assert forces[-1] == pytest.approx(-mu_k * normal, rel=1e-9)  # 5 mm, 130 bristle lengths
    assert block.force(-v, normal, 1.0, mu_k, 0.0, NOMINAL, dt) > forces[-1]  # turned round


def test_a_coulomb_block_with_full_grip_stays_still_on_the_incline_and_a_slick_one_slides():
    # the blocks uncoupled (no spring, damper or pressure): each on the incline alone; the back
    # one on its silicone (mu_s 1), the front one on its casing (mu_s 0.13 < tan 7.5 deg)
    bench = replace(NOMINAL, friction="coulomb", k=0.0, c=0.0)
    chambers = [air.Chamber(ic.V_EXTREMAL, ic.air_settings(bench)) for _ in range(3)]
    chambers[0].contact = 1.0
    blocks = [ic.FRICTIONS["coulomb"]() for _ in range(2)]
    x, v, masses = [0.0, 0.0], [0.05, 0.0], (bench.m1, bench.m2)  # the back one pushed uphill
    normals = [m * ic.G * math.cos(bench.theta) for m in masses]
    dt = ic.DAQ / ic.SUBSTEPS
    for i in range(5000):  # 1 s
        ic._move(bench, chambers, blocks, x, v, masses, normals, i * dt, dt)
        if i == 2500:
            held = x[0]
    assert v[0] == 0.0 and x[0] == held > 0  # stopped within the step it turned, then held
    mu_k = bench.mu_ratio * bench.mu_s_low  # sliding down from rest under kinetic friction
    a = ic.G * (math.sin(bench.theta) - mu_k * math.cos(bench.theta))
    assert v[1] == pytest.approx(-a * 1.0, rel=1e-3)


def test_a_held_camera_changes_only_at_frames_and_more_often_at_more_frames():
    outs = {fps: ic.run(replace(NOMINAL, video_hold=True, video_fps=fps, video_delay=0.05),
                        1.5) for fps in (30.0, 60.0)}
    for fps, out in outs.items():
        t = out["time"]
        for b in range(2):
            changed = t[1:][np.diff(out["x"][:, b]) != 0]
            since = (changed - 0.05) % (1 / fps)  # time since the last frame arrived
            assert np.all((since < ic.DAQ + 1e-9) | (since > 1 / fps - 1e-9))
    distinct = {fps: len(np.unique(out["x"][:, 1])) for fps, out in outs.items()}
    assert distinct[60.0] > 1.5 * distinct[30.0]
