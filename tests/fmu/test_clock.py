"""musclesim.fmu.clock: the time a step ends at, on a master's grid and off it, and a component's
default experiment."""
import pytest

from musclesim.fmu import experiment, step_end


@pytest.mark.parametrize("t0, k, h", [(0.0, 9, 0.001), (0.5, 3, 0.1), (0.0, 0, 0.25),
                                      (1.0, 1000, 1e-3)])
def test_a_step_from_a_grid_point_ends_on_the_next_grid_point(t0, k, h):
    # the master's k-th point is t0 + k h, computed as it computes it; the step ends at point k + 1
    assert step_end(t0, t0 + k * h, h) == t0 + (k + 1) * h


def test_a_step_off_the_grid_or_of_zero_length_ends_at_t_plus_h():
    assert step_end(0.0, 0.0015, 0.001) == 0.0015 + 0.001  # 1.5 steps: not a grid point
    assert step_end(0.0, 0.3, 0.0) == 0.3
    # t + h itself differs from the grid point in the last bit: the grid wins
    assert step_end(0.0, 9 * 0.001, 0.001) == 0.01 != 9 * 0.001 + 0.001


def test_a_components_experiment_starts_at_zero():
    e = experiment(2.5, 0.01)
    assert (e.start_time, e.stop_time, e.step_size) == (0.0, 2.5, 0.01)
