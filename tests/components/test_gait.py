"""Peristaltic gait sequencer (§gait): phase order and durations, mirror image, reversal, FMU."""
import numpy as np
import pytest
from fmpy import simulate_fmu

from musclesim.components.crawler.gait import GaitParams, references

P = GaitParams(p_central=5e3, p_anchor1=2e3, p_anchor2=3e3, p_off=-100.0)
OFF = P.p_off
# forward stride (§gait): (p_ref1, p_ref_c, p_ref2) per phase
FORWARD = {1: (2e3, OFF, OFF), 2: (2e3, 5e3, OFF), 3: (2e3, 5e3, 3e3), 4: (OFF, OFF, 3e3)}
BACKWARD = {1: (OFF, OFF, 3e3), 2: (OFF, 5e3, 3e3), 3: (2e3, 5e3, 3e3), 4: (2e3, OFF, OFF)}


def sample(p, stop_time, step=1e-3):
    """References at a time accumulated step by step, as a master does: rows of 6 values."""
    t, rows = 0.0, []
    for _ in range(int(round(stop_time / step))):
        rows.append(references(t, p))
        t += step
    return np.array(rows)


def runs(values):
    """(value, length) of each run of equal consecutive values."""
    edges = np.flatnonzero(np.diff(values)) + 1
    starts, ends = np.r_[0, edges], np.r_[edges, len(values)]
    return [(values[s], e - s) for s, e in zip(starts, ends)]


@pytest.mark.parametrize("direction, table", [(1.0, FORWARD), (-1.0, BACKWARD)])
def test_phase_order_durations_and_references_over_strides(direction, table):
    """Phases 1-4 last 0.6, 1.2, 0.6 and 0.6 s (stance split equally) and repeat every 3 s."""
    r = sample(GaitParams(**{**P.__dict__, "direction": direction}), 6.0)
    assert runs(r[:, 3]) == [(1, 600), (2, 1200), (3, 600), (4, 600)] * 2
    assert runs(r[:, 5]) == [(1, 3000), (2, 3000)]
    assert (r[:, 4] == direction).all()
    for row in r:
        assert tuple(row[:3]) == table[row[3]]


def test_backward_is_mirror_image_of_forward():
    """Backward with the anchor pressures swapped = forward with back and front swapped."""
    fwd = sample(P, 3.0)
    bwd = sample(GaitParams(**{**P.__dict__, "direction": -1.0, "p_anchor1": P.p_anchor2,
                               "p_anchor2": P.p_anchor1}), 3.0)
    np.testing.assert_array_equal(bwd[:, [2, 1, 0, 3, 5]], fwd[:, [0, 1, 2, 3, 5]])
    assert (bwd[:, 4] == -1).all() and (fwd[:, 4] == 1).all()


def test_reversal_flips_direction_and_restarts_at_phase_one():
    """§gait bidirectional test: reversal every 32.5 s; the stride cut at 32.5 s is dropped."""
    r = sample(GaitParams(**{**P.__dict__, "t_reverse": 32.5}), 100.0)
    assert runs(r[:, 4]) == [(1, 32500), (-1, 32500), (1, 32500), (-1, 2500)]
    for k in (32500, 65000, 97500):
        assert r[k, 3] == 1 and r[k - 1, 3] == 4  # cut in phase 4 (32.5 = 10 x 3 s + 2.5 s)
        assert r[k, 5] == r[k - 1, 5] + 1
    assert runs(r[:, 5])[10:12] == [(11, 2500), (12, 3000)]  # 11 strides started per direction
    # the first stride after a reversal is a whole backward stride from phase 1
    backward = sample(GaitParams(**{**P.__dict__, "direction": -1.0}), 3.0)
    np.testing.assert_array_equal(r[32500:35500, :5], backward[:, :5])


def test_time_accumulated_step_by_step_switches_on_the_exact_sample():
    """0.001 added 1800 times is not exactly 1.8; the switch to phase 3 still comes at sample
    1800."""
    t = sum([1e-3] * 1800)
    assert t != 1.8
    assert references(t, P)[3] == 3 and references(1.8 - 1e-6, P)[3] == 2


@pytest.mark.parametrize("field, value", [("t_protrusion", 0.0), ("t_stance", -1.0),
                                          ("t_reverse", -1.0), ("direction", 0.5),
                                          ("p_central", float("nan")), ("p_anchor2", float("inf"))])
def test_parameter_check_names_the_parameter(field, value):
    with pytest.raises(ValueError, match=field):
        GaitParams(**{field: value}).check()


def test_fmu_gives_the_core_references(fmu_dir):
    params = {"t_reverse": 4.0, "direction": -1.0, "p_central": 7e3, "p_anchor1": 1.5e3,
              "p_anchor2": 2.5e3, "p_off": 50.0, "t_protrusion": 1.0, "t_stance": 1.5}
    names = ["p_ref1", "p_ref_c", "p_ref2", "phase", "stride_direction", "stride"]
    res = simulate_fmu(str(fmu_dir / "GaitSequencer.fmu"), stop_time=10.0, output_interval=1e-2,
                       start_values=params, output=names)
    p = GaitParams(**params)
    expected = np.array([references(t, p) for t in res["time"]])
    np.testing.assert_array_equal(np.column_stack([res[n] for n in names]), expected)
    assert set(res["stride_direction"]) == {-1.0, 1.0} and set(res["phase"]) == {1.0, 2.0, 3.0, 4.0}
    assert res["stride"][-1] == 5  # 2.5 s strides: 2 started per 4 s direction, then the 5th
