"""Loading and writing measured data sets (musclesim.diagnosis.dataset): a good set loads with
its header parsed into Signals, the same data may be checked against another model, and what
`write` writes loads back, byte for byte what it wrote before typed addresses."""
import numpy as np
import pytest

from musclesim.cosim import ParamRef, Signal
from musclesim.diagnosis import dataset
from musclesim.errors import UserError

from dataset_files import COLUMNS, REAL, problems_of, write_set

from conftest import SCENARIOS


def test_good_time_series_set_loads(tmp_path):
    ds = dataset.load(write_set(tmp_path / "set"), scenarios_dir=SCENARIOS)
    assert not ds.scalar_only
    f_a, x_cm = Signal("inputs", "f_a"), Signal("body", "x_cm")
    assert ds.columns == tuple(map(Signal.parse, COLUMNS)) == (f_a, x_cm)
    assert ds.inputs == (f_a,) and ds.outputs == (x_cm,)
    assert ds.units == {f_a: "N", x_cm: "m"}
    assert ds.scenario_path == SCENARIOS / "crawler-ideal.toml"
    np.testing.assert_allclose(ds.time, np.arange(10) * 0.1)
    np.testing.assert_allclose(ds[x_cm], 0.01 * np.arange(10))
    assert ds.parts() == (("first",), ("second",))
    t, cols = ds.experiment("second")
    np.testing.assert_allclose(t, [0.5, 0.6, 0.7, 0.8, 0.9])
    np.testing.assert_allclose(cols[f_a], np.sin([5, 6, 7, 8, 9]))
    assert ds.experiments["second"].metrics["mean_speed"] == dataset.MeasuredMetric(
        0.02, "m/s", 0.001)
    with pytest.raises(UserError, match="no experiment 'third'.*first, second"):
        ds.experiment("third")


def test_scalar_only_real_crawler_set_loads():
    ds = dataset.load(REAL)
    assert ds.scalar_only and ds.columns == ()
    assert ds.parts() == (("forward",), ("backward",))
    fwd, bwd = ds.experiments["forward"], ds.experiments["backward"]
    assert fwd.scenario == "crawler-gait-forward"
    assert fwd.metrics["stride_length"].value == 0.028 and fwd.metrics["stride_length"].unit == "m"
    assert fwd.metrics["mean_speed"].value == 0.0089 and fwd.metrics["mean_speed"].unit == "m/s"
    assert bwd.metrics["stride_length"].value == 0.022 and bwd.metrics["mean_speed"].value == 0.007
    with pytest.raises(UserError, match="scalar-only"):
        ds.experiment("forward")


def test_the_same_data_against_another_model(fmu_dir):
    """--model swaps the experiments' scenarios: the real crawler's data against the ideal
    model, forward and (mirrored) backward; checked against those models' metrics and units."""
    ds = dataset.load(REAL, check_model=True, fmu_dir=fmu_dir, models={
        "*": "crawler-ideal", "backward": "crawler-ideal-backward"})
    assert ds.experiments["forward"].scenario_path == SCENARIOS / "crawler-ideal.toml"
    assert ds.experiments["backward"].scenario_path == SCENARIOS / "crawler-ideal-backward.toml"
    assert ds.experiments["backward"].metrics == dataset.load(REAL).experiments["backward"].metrics
    message = problems_of(REAL, check_model=True, fmu_dir=fmu_dir,
                          models={"sideways": "crawler-ideal", "forward": "no-such-model"})
    assert "model for experiment 'sideways': the data set has no such experiment" in message
    assert "scenario 'no-such-model' not found" in message


def test_what_write_writes_loads_back_byte_for_byte(tmp_path):
    """Signal-keyed columns and ParamRef-keyed conditions are written as ``str()`` of each: the
    same bytes as the string-keyed files written before typed addresses (here by hand)."""
    u, strain = Signal("wire", "u"), Signal("wire", "strain")
    amb = ParamRef("wire", "T_amb")
    time = np.array([0.0, 0.5, 1.0, 1.5])
    cols = {u: np.array([0.1, 0.2, 0.3, 0.4]), strain: np.array([1e-3, 2.5e-3, 3e-3, 1 / 3]),
            Signal("wire", "T"): np.zeros(4)}  # not listed: not written
    dataset.write(tmp_path / "set", time, cols, [u], [strain], "sma-bench-stress",
                  "a hand check", {amb: 291.8}, held_out_fraction=0.5)
    assert (tmp_path / "set" / "data.csv").read_bytes() == (
        b"time,wire.u,wire.strain\n0,0.1,0.001\n0.5,0.2,0.0025\n1,0.3,0.003\n"
        b"1.5,0.4,0.333333333\n")
    assert (tmp_path / "set" / "manifest.toml").read_bytes() == (
        b'format = 2\ndescription = "a hand check"\nscenario = "sma-bench-stress"\n'
        b'inputs = ["wire.u"]\noutputs = ["wire.strain"]\n\n[split]\n'
        b'held_out_fraction = 0.5\n\n[conditions]\n"wire.T_amb" = 291.8\n')
    ds = dataset.load(tmp_path / "set", scenarios_dir=SCENARIOS)
    assert ds.inputs == (u,) and ds.outputs == (strain,) and ds.columns == (u, strain)
    assert ds.values() == {amb: 291.8}
    np.testing.assert_array_equal(ds[strain], np.array([1e-3, 2.5e-3, 3e-3, 0.333333333]))
    assert ds.parts() == (("all/train",), ("all/held_out",))

