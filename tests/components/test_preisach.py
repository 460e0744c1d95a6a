"""The forward Preisach model (components/sma/preisach.py, §preisach): hand-derived cases,
Preisach properties, memory rules and the out-of-range policy."""
import copy
import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from musclesim.hysteresis import timing as bench
from musclesim.components.sma.analytic import sma_like_surface, uniform
from musclesim.components.sma.preisach import (GRID_TEMPS, STRESSES, Hypersurface, MemoryParams,
                                               PreisachModel, RangeWarning, stack_strain,
                                               strain_falling, strain_rising)

C = 2e-5  # 1/C^2, density of the uniform surface: F(130, 30) = 0.1
UNIFORM = Hypersurface.from_function(uniform(C), GRID_TEMPS, [125e6])
# uniform density scaled by stress, five levels: F linear in stress is then exact
UNIFORM_5 = Hypersurface.from_function(lambda a, b, s: uniform(C)(a, b, s) * s / 125e6)
SMA = sma_like_surface()
NO_TOL = MemoryParams(tol=0.0)
temps = st.floats(30.0, 130.0)
paths = st.lists(temps, min_size=1, max_size=30)
stresses = st.floats(105e6, 145e6)


def run(surface, path, sigma=125e6, params=None):
    """Strain after each input of `path` (stress constant, or one value per input)."""
    sigmas = sigma if isinstance(sigma, list) else [sigma] * len(path)
    m = PreisachModel(surface, params)
    return [m.step(T, s) for T, s in zip(path, sigmas)]


@pytest.mark.parametrize("path, expected", [
    pytest.param([90], [1800], id="heat-30-90"),
    pytest.param([90, 50], [1800, 1000], id="cool-to-50"),
    pytest.param([90, 50, 70], [1800, 1000, 1200], id="minor-rise-to-70"),
    pytest.param([90, 50, 70, 60], [1800, 1000, 1200, 1150], id="minor-fall-to-60"),
    pytest.param([90, 50, 70, 60, 95], [1800, 1000, 1200, 1150, 2112.5], id="wipe-all-at-95"),
    pytest.param([90, 50, 70, 60, 80], [1800, 1000, 1200, 1150, 1450], id="wipe-70-at-80"),
    pytest.param([90, 50, 30, 60], [1800, 1000, 0, 450], id="back-to-b0-empties"),
])
def test_uniform_density_by_hand(path, expected):
    """Uniform density c: eps = c times the switched-on area of the Preisach triangle, e.g.
    after 30 -> 90 -> 50 -> 70 -> 60 the area is 1800 - 800 + 200 - 50; at 80 the loop 70/60
    is wiped: 1800 - 800 + (80 - 50)^2 / 2. Grid extrema make bilinear interpolation exact."""
    assert run(UNIFORM, path, params=NO_TOL) == pytest.approx([C * e for e in expected],
                                                                rel=1e-12)


def test_uniform_density_off_grid_within_interpolation_error():
    """Along b = 30 C the bilinear surface is linear in a; (a - b)^2 / 2 is then off by at most
    h^2 / 8 = 3.125 C^2 (times c), reached mid-cell."""
    for T in np.linspace(30, 130, 41):
        eps = PreisachModel(UNIFORM).reset(T, 125e6)
        assert abs(eps - C * (T - 30) ** 2 / 2) <= C * 25 / 8 * (1 + 1e-9)
    assert PreisachModel(UNIFORM).reset(77.5, 125e6) == pytest.approx(C * 1131.25)


@given(st.lists(temps, min_size=1, max_size=40))
def test_linear_surface_has_no_hysteresis(path):
    """F = k (a - b) is the density of reversible hysterons only: the §preisach sums telescope
    to eps = k (T - b0) after any history (checks the diagonal cells and both formulas)."""
    lin = Hypersurface.from_function(lambda a, b, s: 1e-4 * (a - b), GRID_TEMPS, [1e8])
    out = run(lin, path, 1e8, NO_TOL)
    assert out == pytest.approx([1e-4 * (T - 30) for T in path], abs=1e-15)


@given(paths, stresses)
def test_model_equals_spec_formulas_at_constant_stress(path, sigma):
    m = PreisachModel(SMA, NO_TOL)
    for T in path:
        eps = m.step(T, sigma)
        E = m.extrema

        def F(a, b):
            return SMA.F(a, b, sigma)
        if m.rising:
            expected = strain_rising(F, E[1::2] + [m.X], E[0::2])
        else:
            expected = strain_falling(F, E[1::2], E[0::2] + [m.X])
        assert eps == pytest.approx(expected, abs=1e-14)


@given(st.lists(st.tuples(temps, stresses), min_size=1, max_size=60),
       st.sampled_from([0.0, 0.01, 2.0]))
def test_prefix_sums_equal_direct_evaluation(inputs, tol):
    """Under time-varying stress each term keeps the stress of its extremum (§preisach)."""
    m = PreisachModel(SMA, MemoryParams(tol=tol))
    for T, sigma in inputs:
        eps = m.step(T, sigma)
        assert eps == pytest.approx(m.direct_strain(), abs=1e-14)
        assert eps == pytest.approx(stack_strain(SMA, m.extrema, m.stresses, m.X, sigma),
                                    abs=1e-14)


def test_frozen_terms_keep_their_stress():
    """Heat at 145 MPa, cool at 105 MPa: eps = F(90, 30; 145) - F(90, 60; 105)."""
    m = PreisachModel(UNIFORM_5, NO_TOL)
    m.step(90.0, 145e6)
    eps = m.step(60.0, 105e6)
    assert eps == pytest.approx(UNIFORM_5.F(90, 30, 145e6) - UNIFORM_5.F(90, 60, 105e6))


@given(paths, st.floats(0.0, 1.0), paths)
def test_wiping_out_of_all_history(history, frac, continuation):
    """After a maximum above every earlier one, the earlier extrema no longer matter."""
    top = max(history) + frac * (130.0 - max(history))
    with_history = run(SMA, history + [top] + continuation)[len(history):]
    assert with_history == pytest.approx(run(SMA, [top] + continuation), abs=1e-15)


@given(st.lists(temps, min_size=5, max_size=5, unique=True), paths)
def test_wiping_out_of_a_minor_loop(points, continuation):
    """30 -> A -> m -> r1 -> r2 -> M with A > M > r1 > r2 > m: the loop r1/r2 is wiped at M."""
    m, r2, r1, M, A = sorted(points)
    with_loop = run(SMA, [A, m, r1, r2, M] + continuation)[4:]
    assert with_loop == pytest.approx(run(SMA, [A, m, M] + continuation)[2:], abs=1e-15)


@given(paths, paths, st.floats(30.0, 125.0), st.floats(0.5, 40.0), st.floats(0, 1),
       st.floats(0, 1), stresses)
def test_congruency_of_minor_loops(pre_a, pre_b, T1, amp, fa, fb, sigma):
    """Minor loops between the same bounds T1 < T2 are congruent after different histories
    (each history ends above T2, then at T1)."""
    T2 = min(T1 + amp, 130.0)
    cycle = list(np.linspace(T1, T2, 12)) + list(np.linspace(T2, T1, 12)[1:])
    loops = []
    for pre, f in ((pre_a, fa), (pre_b, fb)):
        out = run(SMA, pre + [T2 + f * (130.0 - T2)] + cycle, sigma, NO_TOL)[len(pre) + 1:]
        loops.append(np.array(out) - out[0])
    assert loops[0] == pytest.approx(loops[1], abs=1e-14)


@given(st.lists(temps, min_size=2, max_size=20), st.integers(2, 7), stresses)
def test_rate_independence(knots, k, sigma):
    """The same input path sampled k times finer gives the same strain at the common points."""
    fine = [knots[0]] + [float(x) for a, b in zip(knots, knots[1:])
                         for x in np.linspace(a, b, k + 1)[1:]]
    fine_out = run(SMA, fine, sigma)[::k]
    assert fine_out == pytest.approx(run(SMA, knots, sigma), abs=1e-14)


@given(paths, stresses)
def test_strain_within_zero_and_max(path, sigma):
    top = SMA.F(130.0, 30.0, sigma)
    assert all(-1e-15 <= e <= top + 1e-15 for e in run(SMA, path, sigma))


@pytest.mark.parametrize("sigma", STRESSES)
def test_major_loop_closes(sigma):
    up, down = np.linspace(30, 130, 201), np.linspace(130, 30, 201)
    out = run(SMA, list(up) + list(down[1:]), sigma)
    assert out[200] == pytest.approx(SMA.F(130.0, 30.0, sigma), rel=1e-12)
    assert out[-1] == 0.0
    assert np.all(np.diff(out[:201]) >= 0) and np.all(np.diff(out[200:]) <= 0)
    assert out[100] < out[300] - 0.01  # 80 C: heating branch well below cooling branch


def test_reversals_within_tolerance_make_no_entry():
    m = PreisachModel(SMA)  # tol 0.01 C
    m.step(80.0, 125e6)
    held = [m.step(T, 125e6) for T in (79.995, 79.991, 80.0, 79.999)]
    assert m.extrema == [30.0] and m.rising
    assert held[:2] == [held[3]] * 2  # inside the band the input counts as 80 C
    m.step(79.98, 125e6)
    assert m.extrema == [30.0, 80.0] and not m.rising


@pytest.mark.parametrize("bound, error", [(16, 0.05), (64, 0.001)])
def test_bounded_stack_forgets_the_least_important_pair(bound, error):
    """120 nested reversals converging on 80 C: the stack stays within its bound and the strain
    stays close to the unbounded memory's (forgotten pairs change it little)."""
    path = [80 + 45 * (-0.93) ** k for k in range(120)]
    bounded = PreisachModel(SMA, MemoryParams(max_extrema=bound))
    free = PreisachModel(SMA, MemoryParams(max_extrema=1000))
    for T in path:
        eps = bounded.step(T, 125e6)
        assert len(bounded.extrema) <= bound
        assert eps == pytest.approx(bounded.direct_strain(), abs=1e-14)
        assert abs(eps - free.step(T, 125e6)) < error * SMA.F(130, 30, 125e6)
    assert len(free.extrema) == 120


def test_reset_starts_fully_martensitic():
    m = PreisachModel(SMA)
    m.step(120.0, 125e6)
    m.step(60.0, 125e6)
    assert m.reset(30.0, 125e6) == 0.0 and m.extrema == [30.0]
    assert m.reset(90.0, 125e6) == pytest.approx(SMA.F(90, 30, 125e6))


def test_deepcopy_saves_and_restores_the_state():
    m = PreisachModel(SMA)
    for T in (110, 50, 90, 70):
        m.step(T, 120e6)
    saved = copy.deepcopy(m)
    assert saved.surface is m.surface
    ahead = [m.step(T, 130e6) for T in (85, 60, 100)]
    assert [saved.step(T, 130e6) for T in (85, 60, 100)] == ahead


@settings(max_examples=60)
@given(st.lists(st.tuples(temps, st.sampled_from([110e6, 125e6, 140e6])), min_size=1,
                max_size=40),
       st.lists(st.floats(-3.0, 3.0), min_size=1, max_size=6),
       st.sampled_from([0.0, 0.01, 2.0]))
def test_peek_is_step_on_a_copy_bit_for_bit(inputs, offsets, tol):
    """peek(T, sigma) returns what step would on the present memory, to the bit, and leaves the
    memory as it was: near trials (the running term moving, a reversal within tol), reversals
    that record, wipe out or empty the memory, a new stress, temperatures beyond the grid."""
    m, last = PreisachModel(SMA, MemoryParams(tol=tol)), SMA.s_lo  # the stress it starts at

    def memory():  # the model's state but its warnings given, which peek counts as given too
        return {k: v for k, v in copy.deepcopy(m.__dict__).items() if k != "_warned"}

    for T, sigma in inputs:
        # trials around the present input and around the stack's extrema (wiping-out's edges)
        trials = [T + d for d in offsets] + [e + d for e in m.extrema[-3:] for d in (-1e-9, 0.0)]
        for trial in trials + [25.0, 140.0]:
            for s in (sigma, last, 125e6):
                before = memory()
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", RangeWarning)
                    expected = copy.deepcopy(m).step(trial, s)
                    assert m.peek(trial, s) == expected
                assert memory() == before
        m.step(T, sigma)
        last = sigma


def test_single_stress_surface_ignores_stress():
    flat = SMA.at_stress(125e6)
    m = PreisachModel(flat)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert m.step(90.0, 400e6) == pytest.approx(SMA.F(90, 30, 125e6))


def test_out_of_range_temperature_is_clamped_with_one_warning():
    m = PreisachModel(SMA)
    with pytest.warns(RangeWarning, match=r"temperature 140 C at t = 1\.5 s .*\[30, 130\] C"):
        assert m.step(140.0, 125e6, t=1.5) == pytest.approx(SMA.F(130, 30, 125e6))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m.step(20.0, 125e6, t=2.0)  # already warned for temperature: no second warning


def test_out_of_range_stress_is_clamped_with_one_warning():
    m = PreisachModel(SMA)
    with pytest.warns(RangeWarning, match=r"stress 1\.6e\+08 Pa at t = 3 s .*1\.05e\+08, "
                                          r"1\.45e\+08\] Pa"):
        assert m.step(90.0, 160e6, t=3.0) == pytest.approx(SMA.F(90, 30, 145e6))
    with pytest.warns(RangeWarning, match="stress 2e"):
        SMA.F(90.0, 30.0, 200e6)


def test_nan_input_is_an_error():
    m = PreisachModel(SMA)
    with pytest.raises(ValueError, match="temperature is NaN at t = 4 s"):
        m.step(math.nan, 125e6, t=4.0)
    with pytest.raises(ValueError, match="stress is NaN"):
        m.step(80.0, math.nan)


def test_memory_params_are_checked():
    with pytest.raises(ValueError, match="tol"):
        PreisachModel(SMA, MemoryParams(tol=-1.0))
    with pytest.raises(ValueError, match="max_extrema"):
        PreisachModel(SMA, MemoryParams(max_extrema=3))


def test_bench_reports_per_step_times():
    """`musclesim bench preisach` (timings are not asserted: tests never assert wall-clock)."""
    report = bench.preisach(n=2000, repeat=1)
    assert {"forward_us", "inverse_us", "call_us", "forward_ratio", "inverse_ratio"} <= set(report)
    assert all(report[k] > 0 for k in ("forward_us", "inverse_us", "call_us"))
    assert "us/step" in bench.format_preisach(report)


# --- the memory as an array (the compiled kernels' form) -------------------------------------

def _pm_state(m):
    return m.extrema, m.prefix, m.stresses, m.rising, m.X


def _mem_state(mem):
    from musclesim.components.sma import preisach as pr
    n, cap = int(mem[pr.M_N]), int(mem[pr.M_CAP])
    return ([*mem[pr.M_HEAD:pr.M_HEAD + n]], [*mem[pr.M_HEAD + cap:pr.M_HEAD + cap + n]],
            [*mem[pr.M_HEAD + 2 * cap:pr.M_HEAD + 2 * cap + n]], bool(mem[pr.M_RISING]),
            mem[pr.M_X])


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(temps, stresses), min_size=1, max_size=80),
       st.sampled_from([MemoryParams(), MemoryParams(tol=0.0, max_extrema=4),
                        MemoryParams(tol=0.5, max_extrema=6)]),
       st.sampled_from([SMA, UNIFORM, UNIFORM_5, SMA.at_stress(120e6)]))
def test_array_memory_is_the_model_bit_for_bit(inputs, params, surface):
    """`mem_reset`/`mem_step`/`mem_peek` (the kernels' Preisach memory, fixed capacity
    max_extrema + 1) give the model's strains and stack bit for bit, forgetting pairs included."""
    from musclesim.components.sma import preisach as pr
    from musclesim.components.sma.surface import pack
    s = pack(surface)
    model = PreisachModel(surface, params)
    mem, trial = pr.memory(params), pr.memory(params)
    (T0, s0), rest = inputs[0], inputs[1:]
    assert pr.mem_reset(s, mem, T0, s0) == model.reset(T0, s0)
    for T, sigma in rest:
        assert pr.mem_peek(s, mem, trial, T, sigma) == model.peek(T, sigma)
        assert pr.mem_step(s, mem, T, sigma) == model.step(T, sigma)
        assert _mem_state(mem) == _pm_state(model)
        assert int(mem[pr.M_N]) <= int(mem[pr.M_CAP])


def test_array_surface_is_F_bit_for_bit():
    from musclesim.components.sma.surface import pack, surface_F
    rng = np.random.default_rng(3)
    for surface in (SMA, UNIFORM, SMA.at_stress(120e6)):
        s = pack(surface)
        for a, b, sigma in zip(rng.uniform(25, 135, 300), rng.uniform(25, 135, 300),
                               rng.uniform(100e6, 150e6, 300)):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RangeWarning)
                assert surface_F(s, a, b, sigma) == surface.F(a, b, sigma)
