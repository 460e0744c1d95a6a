"""Box coordinates of a fit on hand-made numbers: the scan's points, the scan itself on a known
cost, the difference step toward the inside, intervals clipped to the box."""
import numpy as np
import pytest

from musclesim.diagnosis.box import axis, box_intervals, moved, period_axis, scan, step
from musclesim.diagnosis.thresholds import PERIOD_POINTS


def test_the_scan_points_crowd_near_the_start_and_a_period_is_covered_evenly():
    assert axis(0.0) == [0.0, 0.125, 0.5, 1.0]
    assert axis(0.5) == [0.0, 0.25, 0.4375, 0.5, 0.5625, 0.75, 1.0]
    points = period_axis(0.9, 0.5)  # a period of half the box from 0.9: wrapped into it
    assert len(points) == PERIOD_POINTS and all(0 <= p <= 1 for p in points)
    gaps = np.diff(sorted(p % 0.5 for p in points))
    assert gaps == pytest.approx(np.full(PERIOD_POINTS - 1, 0.5 / PERIOD_POINTS))
    assert step(0.2) == 1e-3 and step(0.8) == -1e-3  # toward the inside


def test_the_scan_starts_from_the_best_point_and_says_whether_anything_changed():
    ran = []
    cost = lambda z: float((z[0] - 0.5) ** 2 + (z[1] - 1.0) ** 2)  # noqa: E731
    start, applicable = scan(np.array([0.0, 0.0]), [axis(0.0), axis(0.0)], cost, ran.extend)
    assert list(start) == [0.5, 1.0] and applicable
    assert len(ran) == 1 + 3 + 3  # the start and each axis's points, run together first
    flat, applicable = scan(np.array([0.2]), [axis(0.2)], lambda z: 1.0, ran.extend)
    assert list(flat) == [0.2] and not applicable
    z = np.array([0.1, 0.2])
    assert list(moved(z, 1, 0.7)) == [0.1, 0.7] and list(z) == [0.1, 0.2]


def test_box_intervals_are_196_sigma_clipped_to_the_box():
    J = np.eye(2) * np.array([[100.0], [0.5]])  # the first pinned, the second hardly
    (a0, a1), (b0, b1) = box_intervals(J, np.array([0.5, 0.5]), [0.0, 10.0], [2.0, 4.0])
    assert (a0, a1) == pytest.approx((1.0 - 2 * 1.96 / 100, 1.0 + 2 * 1.96 / 100))
    assert (b0, b1) == (10.0, 14.0)  # 1.96 / 0.5 of the box each way: the whole box
    (c0, c1), _ = box_intervals(np.zeros((2, 2)), np.array([0.5, 0.5]), [0.0, 0.0], [1.0, 1.0])
    assert (c0, c1) == (0.0, 1.0)  # singular: its bounds
