"""The monolithic reference of the ideal-actuation crawler (components/crawler/monolithic.py):
time counted as the master counts it, rest without actuation, momentum kept without friction,
and the stored reference result is what it writes."""
import numpy as np
import pytest

from musclesim.components.crawler import body, friction, inputs
from musclesim.components.crawler.monolithic import simulate_ideal, write_reference

FREE = friction.FrictionParams(mu_s_high=0.0, mu_k_high=0.0, mu_s_low=0.0, mu_k_low=0.0)


def test_times_are_counted_as_the_master_counts_them():
    t, x = simulate_ideal(step=1e-3, stop_time=0.5)
    assert t.tolist() == [k * 1e-3 for k in range(501)] and x.shape == (501, 4)
    assert np.array_equal(x[0], np.zeros(4))


def test_without_actuation_nothing_moves():
    still = inputs.InputParams(f_mean=0.0, f_amp=0.0)
    _, x = simulate_ideal(inputs_p=still, stop_time=2.0)
    assert np.array_equal(x, np.zeros_like(x))


def test_without_friction_the_actuator_cannot_move_the_centre_of_mass():
    p = body.BodyParams(m1=0.3, m2=0.2)
    _, x = simulate_ideal(body_p=p, friction_p=(FREE, FREE), stop_time=3.0)
    momentum = p.m1 * x[:, 1] + p.m2 * x[:, 3]
    assert np.max(np.abs(momentum)) < 1e-12
    assert np.max(np.abs(x[:, 0] - x[:, 2])) > 1e-3  # while the blocks move apart and back


def test_the_gait_moves_forward_and_the_stored_reference_is_what_it_writes(tmp_path):
    _, x = simulate_ideal(stop_time=5.0)
    assert x[-1, 0] > 0 and x[-1, 2] > 0  # §ideal-actuation: the nominal gait crawls forward
    write_reference(tmp_path / "ref.csv", stop_time=1.0, every=10)
    table = np.loadtxt(tmp_path / "ref.csv", delimiter=",", skiprows=1)
    t, x = simulate_ideal(stop_time=1.0)
    assert np.array_equal(table, np.column_stack([t, x])[::10])
    assert (tmp_path / "ref.csv").read_text().startswith("time,x1,v1,x2,v2\n")
    assert table.shape == (101, 5) and table[1, 0] == pytest.approx(0.01)
