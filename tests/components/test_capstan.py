"""The capstan multiplier's core (components/multiplier/capstan.py, §capstan-multiplier): tensions
by hand, equivalences with the straight wire, voltage sharing, effects, parameter errors."""
import math

import numpy as np
import pytest

from musclesim.components.multiplier import capstan
from musclesim.components.multiplier.slaves import CapstanMultiplier
from musclesim.components.sma.slaves import SmaWire
from musclesim.components.sma.thermal import ThermalParams

from conftest import in_process
from component_runs import OUTPUTS, heat_cool, run_wire



def test_tension_steps_by_exp_mu_theta_at_each_contact_by_hand():
    # §capstan-multiplier: mu_f 0.0237 on PTFE, about pi per tube: 1.0773 per contact (1.060-1.085)
    p = capstan.CapstanParams()
    ratios = capstan.tension_ratios(p)
    by_hand = math.exp(0.0237 * math.pi)
    assert by_hand == pytest.approx(1.07730, abs=1e-5) and 1.060 < by_hand < 1.085
    assert ratios == pytest.approx([by_hand ** 2, by_hand, 1.0], rel=1e-15)
    assert ratios[0] == pytest.approx(1.16057, abs=1e-5) and ratios[2] == 1.0
    # other wraps per contact: segment 1 (at the clamp) carries both contacts' steps
    p = capstan.CapstanParams(wraps=(math.pi / 2, 2 * math.pi), mu_f=0.1)
    assert capstan.tension_ratios(p) == pytest.approx(
        [math.exp(0.1 * 2.5 * math.pi), math.exp(0.1 * 2 * math.pi), 1.0], rel=1e-15)


def test_three_segments_without_friction_move_three_times_a_third():
    # current drive: every segment heats like the straight wire of its length, per unit length
    # the same; the end displacement is the sum of three equal contractions
    u, f = heat_cool(0.5), np.full(3000, 1.47)
    straight = run_wire(in_process(SmaWire, "wire", length=0.214 / 3, drive_current=1.0), u, f)
    mult = run_wire(in_process(CapstanMultiplier, "mult", mu_f=0.0, drive_current=1.0), u, f,
               names=OUTPUTS + ("segment[1]_T", "segment[2]_strain"))
    np.testing.assert_allclose(mult["segment[1]_T"], straight["T"], rtol=1e-13)
    np.testing.assert_allclose(mult["segment[2]_strain"], straight["strain"], rtol=1e-12,
                               atol=1e-15)
    np.testing.assert_allclose(mult["flange_s"], 3 * straight["flange_s"], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(mult["R"], 3 * straight["R"], rtol=1e-13)


def test_series_segments_share_the_voltage_by_resistance():
    assert capstan.segment_voltages(6.0, [1.0, 2.0, 3.0]) == pytest.approx([1.0, 2.0, 3.0])
    assert capstan.segment_voltages(6.0, [4.2]) == [6.0]


def test_capstan_friction_changes_the_displacement_not_the_heating():
    # friction raises the clamp-side stresses, which shifts their transformation (§preisach)
    u, f = heat_cool(6.0, on=0.25, total=1.0), np.full(1000, 1.47)
    base = run_wire(in_process(CapstanMultiplier, "m0", mu_f=0.0), u, f)
    fric = run_wire(in_process(CapstanMultiplier, "m1"), u, f)
    assert not np.array_equal(base["flange_s"], fric["flange_s"])
    assert np.array_equal(base["T"][:2], fric["T"][:2])


def test_composition_shift_makes_the_wire_transform_hotter():
    u, f = heat_cool(6.0, on=0.3, total=0.3), np.full(300, 1.47)
    base = run_wire(in_process(CapstanMultiplier, "m0"), u, f)
    shifted = run_wire(in_process(CapstanMultiplier, "m1", composition_shift=10.0), u, f)
    assert np.array_equal(base["T"][:20], shifted["T"][:20])
    half = np.argmax(base["strain"] > 0.5 * base["strain"].max())
    assert shifted["strain"][half] < 0.5 * base["strain"].max()


def test_contact_heat_loss_is_each_contact_conductance_shared_by_its_two_segments():
    # by hand: the extra conductance (h_i - h) pi d L_i of all segments together is one
    # contact_conductance per contact, half on each side; none without contacts or at 0
    p = capstan.CapstanParams(segment_lengths=(0.05, 0.0, 0.1), contact_conductance=3e-3)
    lengths = capstan.segment_lengths(p)
    hs = capstan.segment_h(p, lengths)
    extra = [(h - p.wire.h) * math.pi * p.wire.diameter * L for h, L in zip(hs, lengths)]
    assert extra == pytest.approx([1.5e-3, 3e-3, 1.5e-3])
    assert capstan.segment_h(capstan.CapstanParams(n_segments=1), [0.214]) == [p.wire.h]
    assert capstan.segment_h(capstan.CapstanParams(), [0.1, 0.05, 0.064]) == [p.wire.h] * 3


def test_contact_heat_loss_cools_the_wire_and_its_steady_excess_by_hand():
    # two equal segments over one contact, a steady current that holds the wire austenitic
    # (fixed resistance): the excess temperature settles at P / (h A_s + G)
    G, u, f = 4e-3, np.full(6000, 0.4), np.full(6000, 1.47)
    runs = {g: run_wire(in_process(CapstanMultiplier, f"m{g}", drive_current=1.0, n_segments=2.0,
                              contact_conductance=g), u, f, dt=2e-3) for g in (0.0, G)}
    t = ThermalParams(length=0.214)
    conductance = t.h * math.pi * t.diameter * t.length
    for g, r in runs.items():
        assert r["T"][-1] - 293.15 == pytest.approx(r["P"][-1] / (conductance + g), rel=2e-3)
    assert runs[G]["T"][-1] < runs[0.0]["T"][-1] - 50


@pytest.mark.parametrize("params, message", [
    ({"n_segments": 7.0}, "n_segments must be an integer within 1..6"),
    ({"n_segments": 2.5}, "n_segments must be an integer"),
    ({"mu_f": -0.1}, "mu_f must be non-negative"),
    ({"segment_length[1]": 0.1, "segment_length[2]": 0.1, "segment_length[3]": 0.1},
     "segment_lengths add up to 0.3 m, not the wire's length 0.214 m"),
    ({"segment_length[1]": 0.3}, "segment_lengths leave no length"),
    ({"wrap[1]": -1.0}, "wraps must be non-negative"),
    ({"contact_conductance": -1e-3}, "contact_conductance must be non-negative"),
])
def test_bad_parameters_are_named(params, message):
    slave = in_process(CapstanMultiplier, "mult")
    for name, value in params.items():
        setattr(slave, name, value)
    with pytest.raises(ValueError, match=message):
        slave.setup()


def test_unequal_segments_add_up():
    p = capstan.CapstanParams(segment_lengths=(0.05, 0.0, 0.1))
    assert capstan.segment_lengths(p) == pytest.approx([0.05, 0.064, 0.1])
