"""A measured data set as values (musclesim.diagnosis.measured): experiments and their parts,
the stated values, each experiment's scenario with them."""
from dataclasses import replace

import numpy as np
import pytest

from musclesim.cosim import ParamRef, Signal
from musclesim.diagnosis import dataset
from musclesim.diagnosis.measured import part_mask
from musclesim.errors import UserError

from dataset_files import SCALAR, write_set

from conftest import SCENARIOS


def test_blocked_time_split_of_a_single_experiment(tmp_path):
    manifest = 'scenario = "x"\ninputs = ["inputs.f_a"]\noutputs = ["body.x_cm"]\n' \
               "[split]\nheld_out_fraction = 0.3\n"
    ds = dataset.load(write_set(tmp_path / "set", manifest))
    assert list(ds.experiments) == ["all"] and ds.experiments["all"].span == (0.0, 0.9)
    train, held = ds.parts()
    assert (train, held) == (("all/train",), ("all/held_out",))
    t_train, _ = ds.experiment("all/train")
    t_held, cols = ds.experiment("all/held_out")
    np.testing.assert_allclose(t_train, np.arange(7) * 0.1)  # cut at 0.63 s
    np.testing.assert_allclose(t_held, [0.7, 0.8, 0.9])
    assert len(cols[Signal("body", "x_cm")]) == 3


def test_open_values_and_an_experiments_own_conditions_load(tmp_path):
    manifest = SCALAR + ('[[calibrate]]\nset = ["body.k"]\nbounds = [150.0, 250.0]\n'
                         'why = "the actuator\'s stiffness"\n'
                         '[[calibrate]]\nset = ["friction1.mu_k_low", "friction2.mu_k_low"]\n'
                         'bounds = [0.05, 0.2]\n')
    ds = dataset.load(write_set(tmp_path / "set", manifest, rows=False))
    assert ds.calibrate == (
        dataset.OpenValue((ParamRef("body", "k"),), 150.0, 250.0, "the actuator's stiffness"),
        dataset.OpenValue((ParamRef("friction1", "mu_k_low"), ParamRef("friction2", "mu_k_low")),
                          0.05, 0.2))
    # the set's conditions, then the experiment's own (which may override them)
    c, k = ParamRef("body", "c"), ParamRef("body", "k")
    assert list(ds.values("a").items()) == [(c, 1.2), (k, 210.0)]
    assert ds.values("b") == ds.values() == {c: 1.2}


def test_each_experiments_scenario_runs_with_its_stated_values(tmp_path):
    """`scenario_of`: the experiment's scenario file with the set's values, the experiment's own
    over them; a loaded set carries those scenarios and needs the files no more."""
    folder = write_set(tmp_path / "set", SCALAR.replace(
        "[experiments.b]\n", "[experiments.b]\nstop_time = 2.5\n"), rows=False)
    ds = dataset.load(folder, scenarios_dir=SCENARIOS)
    a, b = ds.scenario_of("a"), ds.scenario_of("b")
    assert a.instances["body"].parameters["k"] == 210.0
    assert a.instances["body"].parameters["c"] == b.instances["body"].parameters["c"] == 1.2
    assert b.instances["body"].parameters.get("k") != 210.0 and b.stop_time == 2.5
    carried = ds.loaded()
    carried.experiments["a"] = replace(carried.experiments["a"], scenario_path=tmp_path / "gone")
    assert carried.scenario_of("a") == a


def test_a_part_of_a_span_is_cut_at_the_held_out_fraction():
    """Hand cases: a span [0, 1] with 0.25 held out is cut at 0.75 s, the cut in the held-out
    part; the span is closed; no part means the whole span."""
    t = np.array([-0.5, 0.0, 0.25, 0.5, 0.74, 0.75, 1.0, 1.5])
    assert part_mask(t, (0.0, 1.0)).tolist() == [False, True, True, True, True, True, True,
                                                  False]
    assert part_mask(t, (0.0, 1.0), "train", 0.25).tolist() == [
        False, True, True, True, True, False, False, False]
    assert part_mask(t, (0.0, 1.0), "held_out", 0.25).tolist() == [
        False, False, False, False, False, True, True, False]


def test_a_scalar_only_set_has_no_time_series(tmp_path):
    ds = dataset.load(write_set(tmp_path / "set", SCALAR, rows=False), scenarios_dir=SCENARIOS)
    assert ds.scalar_only and ds.columns == () and ds.parts() == (("a",), ("b",))
    with pytest.raises(UserError, match=r"scalar-only \(no data.csv\); experiment 'a'"):
        ds.experiment("a")
