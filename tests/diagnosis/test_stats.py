"""The diagnosis's statistics on synthetic arrays (no FMU): noise estimate, gaps, lag, block
bootstrap, worst windows."""
import math
import os
import subprocess
import sys
from types import SimpleNamespace

import numpy as np
import pytest

from musclesim.diagnosis import stats
from musclesim.diagnosis.thresholds import BOOTSTRAP, DEVIATES

from conftest import two_blas_kernels


def unit_of(parts, noise=None, time=None, t0=0.0):
    """A stand-in for a diagnosis unit: one run per part array, columns as `noise` names them."""
    noise = noise or {"a.y": 0.01}
    runs = [SimpleNamespace(part=np.asarray(p), experiment=f"e{i}", t0=t0,
                            time=None if time is None else time[i])
            for i, p in enumerate(parts)]
    return SimpleNamespace(observed=tuple(noise), noise=noise, runs=runs)


def test_noise_estimate_recovers_white_noise_on_a_smooth_signal():
    rng = np.random.default_rng(1)
    t = np.linspace(0, 20, 4000)
    smooth = 300 + 40 * np.sin(0.7 * t) + 5 * t
    sigma = 0.05
    assert stats.noise_estimate(smooth + sigma * rng.standard_normal(t.size)) == \
        pytest.approx(sigma, rel=0.05)
    assert stats.noise_estimate(smooth) < 0.01 * sigma  # the curvature alone: next to nothing
    assert stats.noise_estimate(np.array([1.0, 2.0, 3.0])) == 0.0  # too short to tell


def test_gap_is_the_rms_of_a_parts_residuals_by_hand():
    unit = unit_of([[0, 0, 1, 1], [1, 0, 0]], noise={"a.y": 0.1, "b.z": 0.2})
    res = {"a.y": [np.array([5.0, 5.0, 0.3, -0.4]), np.array([math.nan, 9.0, 9.0])],
           "b.z": [np.array([5.0, 5.0, 1.2, 0.0]), np.array([0.5, 9.0, 9.0])]}
    # held out: 0.3, -0.4 (a.y; the nan dropped), 1.2, 0.0, 0.5 (b.z)
    assert stats.gap(unit, res, 1) == pytest.approx(math.sqrt((0.09 + 0.16 + 1.44 + 0.25) / 5))
    assert stats.gap(unit, res, 1, ["a.y"]) == pytest.approx(math.sqrt(0.25 / 2))
    assert stats.gap(unit, res, 0, ["a.y"]) == pytest.approx(math.sqrt((25 + 25 + 81 + 81) / 4))
    assert math.isnan(stats.gap(unit_of([[0, 0]]), {"a.y": [np.zeros(2)]}, 1))
    # b.z's held-out gap, sqrt(1.69 / 3) = 0.75, is 3.75 noise floors: it deviates alone
    assert stats.deviates(unit, res) == (0.75 > DEVIATES * 0.2)
    assert stats.deviates(unit, res)
    assert stats.noise_floor(unit) == pytest.approx(math.sqrt((0.01 + 0.04) / 2))


def test_advance_and_smooth_rate():
    y = np.array([1.0, 2.0, 3.0, 4.0])
    assert stats.advance(y, 0) is y
    assert list(stats.advance(y, 2)) == [3.0, 4.0, 4.0, 4.0]
    t = np.arange(0, 5, 0.01)
    rate = stats.smooth_rate(t, 2.0 * t + 1.0)
    assert np.allclose(rate[20:-20], 2.0)  # the moving average's edges aside


def test_lag_of_a_shifted_sine():
    t = np.arange(0, 20, 0.01)
    model = np.sin(2 * np.pi * 0.5 * t)
    assert stats.lag(t, np.sin(2 * np.pi * 0.5 * (t - 0.3)), model) == pytest.approx(0.3)
    assert stats.lag(t, np.sin(2 * np.pi * 0.5 * (t + 0.12)), model) == pytest.approx(-0.12)
    assert stats.lag(t, np.ones_like(t), model) == 0.0  # a constant has no lag


def test_block_bootstrap_interval_holds_the_true_gap_and_is_seeded():
    rng = np.random.default_rng(3)
    n = 4000
    unit = unit_of([np.r_[np.zeros(1000), np.ones(n - 1000)]])
    res = {"a.y": [0.1 * rng.standard_normal(n)]}
    boot = stats.bootstrap(unit, [res])
    assert boot.shape == (BOOTSTRAP, 1)
    low, high = stats.interval95(boot[:, 0])
    assert low < 0.1 < high and high - low < 0.02
    assert low < stats.gap(unit, res, 1) < high
    assert np.array_equal(boot, stats.bootstrap(unit, [res], seed=0))
    assert not np.array_equal(boot, stats.bootstrap(unit, [res], seed=1))
    # two residual sets resample the same blocks: a set twice as large, a gap exactly twice
    both = stats.bootstrap(unit, [res, {"a.y": [2 * res["a.y"][0]]}])
    assert np.allclose(both[:, 1], 2 * both[:, 0])


def test_split_blocks_and_interval95():
    blocks = stats.split_blocks(np.r_[np.zeros(5, bool), np.ones(45, bool)], count=4)
    assert [b[0] for b in blocks] == [5, 17, 28, 39] and sum(b.size for b in blocks) == 45
    assert stats.split_blocks(np.zeros(3, bool)) == []
    assert stats.interval95(np.arange(1001.0)) == [25.0, 975.0]


def test_worst_windows_find_the_planted_bad_window():
    rng = np.random.default_rng(5)
    time = np.arange(1000) * 0.01
    res = {"a.y": [0.01 * rng.standard_normal(1000)]}
    res["a.y"][0][300:350] += 0.5  # one window of 5 %, 50 samples
    res["a.y"][0][720:740] += 0.2  # a smaller fault, 20 samples in the window from 7 s
    unit = unit_of([np.ones(1000)], time=[time], t0=100.0)
    worst = stats.worst_windows(unit, res, count=2)
    assert worst[0]["experiment"] == "e0"
    assert (worst[0]["t0"], worst[0]["t1"]) == pytest.approx((103.0, 103.49))
    assert worst[0]["gap"] == pytest.approx(0.5, rel=0.05)
    assert worst[1]["t0"] == pytest.approx(107.0)
    assert worst[1]["gap"] == pytest.approx(math.sqrt(20 * 0.2 ** 2 / 50), rel=0.1)


RATE_CHILD = """
import numpy as np
from threadpoolctl import threadpool_info
from musclesim.diagnosis.stats import smooth_rate
t = np.arange(0.0, 120.0, 0.02)
y = np.round(300 + 20 * np.sin(0.3 * t)
             + 0.2 * np.random.default_rng(1).standard_normal(len(t)), 1)
print(smooth_rate(t, y).tobytes().hex())
print(sorted({i["architecture"] for i in threadpool_info() if i["internal_api"] == "openblas"}))
"""


def test_a_rate_of_quantised_data_is_the_same_bits_under_two_blas_kernels():
    """A thermocouple's 0.1 K steps make many rates zero in exact arithmetic; their computed sign
    decides heating or cooling (the regimes), so it may not depend on the CPU's BLAS kernel (it
    did while the moving average was np.convolve's)."""
    out = [subprocess.run([sys.executable, "-c", RATE_CHILD], capture_output=True, text=True,
                          env={**os.environ, "OPENBLAS_CORETYPE": kernel}, timeout=120)
           for kernel in two_blas_kernels()]
    assert all(done.returncode == 0 for done in out), [done.stderr for done in out]
    (rate_a, blas_a), (rate_b, blas_b) = (done.stdout.splitlines() for done in out)
    if blas_a == blas_b:
        pytest.skip(f"numpy's BLAS is no OpenBLAS that OPENBLAS_CORETYPE steers ({blas_a})")
    assert rate_a == rate_b


def test_moving_mean_is_np_convolves_same_mode():
    rng = np.random.default_rng(5)
    for length, n in [(50, 1), (50, 2), (50, 12), (50, 13), (13, 13), (5, 12)]:
        y = rng.standard_normal(length)
        mean = stats.moving_mean(y, n)
        assert mean.shape == y.shape
        if length >= n:  # np.convolve's "same" has max(len(y), n) samples
            assert np.allclose(mean, np.convolve(y, np.ones(n) / n, "same"), rtol=1e-12,
                               atol=1e-15)
    assert list(stats.moving_mean(np.array([3.0, 6.0]), 3)) == [3.0, 3.0]  # zeros beyond ends
