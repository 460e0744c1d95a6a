"""The independent SMA bench's hysteresis (musclesim.benchmark.benches.sma_kinetics): full
transformations with the heating branch above the cooling one, the Clausius-Clapeyron shift,
minor loops from a reversal inside a band."""
import numpy as np
import pytest

from musclesim.benchmark.benches import sma_kinetics as kinetics


def _cycle(stress, lo=20.0, hi=130.0, step=0.25):
    """Heat from `lo` to `hi` and back: (temperatures, fractions) of one volume."""
    up = np.arange(lo, hi + step, step)
    temps = np.concatenate([up, up[::-1]])
    k = kinetics.Kinetics(np.array([lo]), stress)
    return temps, np.array([k.step(np.array([t]))[0] for t in temps])


def test_kinetics_hysteresis_full_transformation_and_clausius_clapeyron():
    temps, xi = _cycle(kinetics.STRESS)
    n = len(temps) // 2
    heat, cool = xi[:n], xi[n:][::-1]  # both on the rising temperature grid
    assert heat[0] == 1.0 and heat[-1] == 0.0 and cool[0] == 1.0  # full transformations
    assert np.all(np.diff(heat) <= 1e-12) and np.all(np.diff(cool) <= 1e-12)
    mid = (temps[:n] > 60) & (temps[:n] < 90)
    assert np.all(heat[mid] > cool[mid] + 0.05)  # the heating branch lies above: hysteresis
    # 70 MPa more shifts every transformation temperature by 70 / CC_SLOPE = 10 K
    temps2, xi2 = _cycle(kinetics.STRESS + 70e6)
    half = [np.interp(-0.5, -x[:n], temps[:n]) for x in (xi, xi2)]
    assert half[1] - half[0] == pytest.approx(70e6 / kinetics.CC_SLOPE, abs=0.05)


def test_a_reversal_inside_the_band_starts_a_minor_loop():
    k = kinetics.Kinetics(np.array([20.0]), kinetics.STRESS)
    for t in np.arange(20.0, 80.0, 0.5):
        k.step(np.array([t]))
    at_turn = k.xi[0]
    k.step(np.array([79.0]))  # cooling from 79.5 C: the martensite band has not begun to act
    assert k.xi[0] >= at_turn and k.xi[0] - at_turn < 0.02
    for t in np.arange(79.0, 20.0, -0.5):
        k.step(np.array([t]))
    assert k.xi[0] == pytest.approx(1.0)
