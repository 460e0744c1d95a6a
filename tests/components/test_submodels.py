"""The SMA wire's submodels (components/sma/submodels.py): each variant is the core function it
stands for, bit for bit, and the cold ends combine the zones as their lengths weigh them."""
import pytest

from musclesim.components.sma import ends, submodels, thermal
from musclesim.components.sma.analytic import sma_like_surface
from musclesim.components.sma.preisach import PreisachModel

P = thermal.ThermalParams()
LATENT = thermal.ThermalParams(latent_heat=20e3)
INPUTS = thermal.ThermalInputs(u=2.0, T_amb=20.0, xi=0.7)


def xi_at(T):
    """A martensite fraction falling across 60-80 C, as a heating branch does."""
    return min(1.0, max(0.0, (80.0 - T) / 20.0))


def test_lumped_is_the_thermal_step_bit_for_bit():
    for T, dt in ((20.0, 4e-4), (75.0, 0.02), (130.0, 1.0)):
        assert submodels.Lumped().step(T, INPUTS, dt, P) == thermal.step(T, INPUTS, dt, P)


def test_lumped_latent_is_the_coupled_step_bit_for_bit():
    for T in (50.0, 70.0, 79.0):
        assert submodels.LumpedLatent().step(T, INPUTS, 0.02, LATENT, xi_at) == \
            thermal.step_coupled(T, INPUTS, 0.02, LATENT, xi_at)[0]
    with pytest.raises(ValueError, match="xi_at"):
        submodels.LumpedLatent().step(70.0, INPUTS, 0.02, LATENT)


def test_the_latent_heat_picks_the_thermal_submodel():
    assert type(submodels.thermal_submodel(P)) is submodels.Lumped
    assert type(submodels.thermal_submodel(LATENT)) is submodels.LumpedLatent


def test_no_ends_is_the_uniform_wire():
    e = submodels.NoEnds()
    e.reset(sma_like_surface())
    assert e.zones == ()
    assert e.strain(0.031, 90.0, 20.0, lambda m, T: 1 / 0) == 0.031  # no zone is asked
    assert e.core_drive(2.5, 0.2, 0.9, P) == 2.5


def test_cold_ends_weigh_the_zones_by_their_length():
    table = [(0.1, 0.5), (0.2, 0.75)]  # shares of the length, excess factors
    e = submodels.ColdEnds(table)
    e.reset(sma_like_surface())
    assert len(e.models) == 2 and all(isinstance(m, PreisachModel) for m in e.models)
    seen = []

    def strain_of(m, T):
        seen.append(T)
        return T / 1000  # a strain that says which temperature it was asked at

    # core at 100 C, air at 20 C: zones at 20 + 0.5 * 80 = 60 C and 20 + 0.75 * 80 = 80 C
    eps = e.strain(0.04, 100.0, 20.0, strain_of)
    assert seen == [60.0, 80.0]
    assert eps == pytest.approx(0.7 * 0.04 + 0.1 * 0.060 + 0.2 * 0.080, rel=1e-15)


def test_cold_ends_heat_the_core_by_its_own_resistance_under_voltage():
    e = submodels.ColdEnds([(0.1, 0.5)])
    current = thermal.ThermalParams(drive="current")
    assert e.core_drive(0.3, 0.2, 0.9, current) == 0.3  # the same current everywhere
    # voltage: the wire's current u / R(xi) heats the core as u R(xi_core) / R(xi) across it
    u = e.core_drive(2.0, 0.2, 0.9, P)
    assert u == 2.0 * thermal.resistance(0.2, P) / thermal.resistance(0.9, P)
    assert thermal.joule_power(u, 0.2, P) == pytest.approx(
        thermal.resistance(0.2, P) * (2.0 / thermal.resistance(0.9, P)) ** 2, rel=1e-14)


def test_end_cooling_picks_the_ends_submodel():
    args = (P.length, P.diameter, 18.0, P.h)
    assert type(submodels.ends_submodel(0.0, *args)) is submodels.NoEnds
    cold = submodels.ends_submodel(0.9, *args)
    assert type(cold) is submodels.ColdEnds and cold.zones == ends.zones(0.9, *args)
