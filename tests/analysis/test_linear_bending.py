"""The bending actuator's linear model (§bending-actuator): its resonance against the hand formula,
the pulse-follow frequency against the first-order thermal corner by hand, its band against the
nonlinear actuator's, and the command line."""
import json
import math

import pytest

from musclesim import cli
from musclesim.analysis import linear_bending
from musclesim.components.bending import actuator, beam
from musclesim.components.sma.reference_wire import ReferenceWire, load_params


def hand_resonance(thickness, tip_mass, modulus_a=28e9):
    """f = sqrt(K / J) / 2 pi for the Rayleigh mode of the module: K = n E b t^3 / 12 L +
    e^2 A (E_A + E_B) / L_w, J = m_tip (z_tip - L / 2)^2 + m_beams L^2 / 20 (default geometry)."""
    L, e, A = 0.01, 1.7e-3, math.pi * 25e-6 ** 2
    K = 2 * 120e9 * 1e-3 * thickness ** 3 / 12 / L + e * e * A * (modulus_a + 28e9) / 0.01
    m_beams = 2 * 1e-3 * thickness * L * 1600.0
    J = tip_mass * (0.013 - L / 2) ** 2 + m_beams * L ** 2 / 20
    return math.sqrt(K / J) / (2 * math.pi)


@pytest.mark.parametrize("thickness, tip_mass", [(0.2e-3, 0.2e-3), (0.3e-3, 0.5e-3)],
                         ids=["default", "stiffer-heavier"])
def test_resonance_matches_the_hand_formula(thickness, tip_mass):
    b = beam.BeamParams(thickness=thickness, tip_mass=tip_mass)
    r = linear_bending.bending(beam_p=b)["resonance"]
    assert r["cold_undamped"] == pytest.approx(hand_resonance(thickness, tip_mass), rel=1e-9)
    # python-control's poles: wire A at the band's modulus
    E_a = actuator.modulus(r_xi(b), actuator.WireLayout())
    assert r["undamped"] == pytest.approx(hand_resonance(thickness, tip_mass, E_a), rel=1e-9)
    assert r["damping_ratio"] < 0.03 + 1e-12
    zeta = r["damping_ratio"]
    assert r["peak"] == pytest.approx(r["undamped"] * math.sqrt(1 - 2 * zeta ** 2), rel=3e-3)
    assert 100 < r["undamped"] < 1000


def r_xi(b):
    """The martensite fraction of wire A at the design's band (the model's operating point)."""
    layout = actuator.WireLayout()
    op = linear_bending.operating_point(linear_bending.BENDING_DESIGN, layout,
                                        actuator.wire_thermal(layout.length), ReferenceWire())
    return op["xi"]


def test_pulse_follow_frequency_is_the_thermal_corner_by_hand():
    """Far below the resonance the chain is first order: the first harmonic's swing over the mean
    is 4 sin(pi d) / (pi d sqrt(1 + (2 pi f tau)^2)); it falls to 1 at the frequency below."""
    r = linear_bending.bending()
    tau, d = r["thermal"]["time_constant"], 0.05
    hand = math.sqrt((4 * math.sin(math.pi * d) / (math.pi * d)) ** 2 - 1) / (2 * math.pi * tau)
    assert r["follow"]["frequency"] == pytest.approx(hand, rel=1e-3)
    at_4hz = 4 * math.sin(math.pi * d) / (math.pi * d * math.hypot(1, 2 * math.pi * 4 * tau))
    assert r["follow"]["ratio_at_design"] == pytest.approx(at_4hz, rel=1e-3)
    # a stricter criterion follows to a lower frequency
    strict = linear_bending.bending({"follow_ratio": 2.0})["follow"]["frequency"]
    assert strict < r["follow"]["frequency"]


def test_band_is_the_linear_thermal_model_of_the_pulses():
    r = linear_bending.bending()
    lo, hi = r["thermal"]["band"]
    # the nonlinear actuator's steady band under the same pulses (scenario bending-one-wire)
    core = actuator.BendingActuator(
        beam.BeamParams(), actuator.WireLayout(), actuator.wire_thermal(0.01),
        actuator.hysteresis_surface(load_params(), 0.196 / (math.pi * 25e-6 ** 2)))
    temps = []
    for k in range(8000):
        core.step(5e-4, (5.0 if k % 500 < 25 else 0.0, 0.0), 20.0)
        if k >= 4000:
            temps.append(core.T[0])
    assert min(temps) == pytest.approx(lo, abs=3.0) and max(temps) == pytest.approx(hi, abs=3.0)


def test_cli_json_and_text(capsys):
    assert cli.main(["linear", "bending", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert set(report) >= {"resonance", "thermal", "follow", "dc_gain"}
    assert cli.main(["linear", "bending"]) == 0
    assert "first resonance" in capsys.readouterr().out
