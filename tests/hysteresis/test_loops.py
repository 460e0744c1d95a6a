"""Loop explorer (issue 3 item 2): reference wire, FORC data sets, text, JSON, plot, bad input."""
import json

import pytest

from musclesim.components.sma.preisach import Hypersurface
from musclesim.components.sma.reference_wire import DEFAULT_PARAMS, ReferenceWire
from musclesim.errors import UserError
from musclesim.hysteresis.loops import loops, loops_main, parse_band

WIRE = ReferenceWire()
BANDS = ["30:130", "50:100", "60:85"]


@pytest.fixture(scope="module")
def forc_file(tmp_path_factory):
    """The reference wire tabulated like an identified data set (§preisach grid and stresses)."""
    path = tmp_path_factory.mktemp("forc") / "wire.csv"
    Hypersurface.from_function(WIRE.F).save(path)
    return path


def test_steady_loop_is_the_forc_increment_and_repeats():
    (r,) = loops(WIRE, 155e6, [(50.0, 100.0)], cycles=4)
    temps, strain = r["curve"]
    assert temps[0] == temps[-1] == 50.0 and temps.max() == 100.0
    assert strain[0] == pytest.approx(strain[-1], abs=1e-15)  # the minor loop closes
    assert r["peak_to_peak"] == pytest.approx(float(WIRE.F(100, 50, 155e6)), rel=1e-9)
    (again,) = loops(WIRE, 155e6, ["50:100"], cycles=2)
    assert again["peak_to_peak"] == r["peak_to_peak"]


def test_text_and_json_report_every_band(tmp_path):
    text = loops_main(155e6, BANDS, plot_path=tmp_path / "loops.png")
    assert text.count("peak-to-peak strain") == 3 and "60-85 C" in text
    assert (tmp_path / "loops.png").stat().st_size > 0
    report = loops_main(155e6, BANDS, as_json=True)
    json.dumps(report)
    assert [r["band_C"] for r in report["loops"]] == [[30, 130], [50, 100], [60, 85]]
    assert report["warnings"] == [] and report["plot"] is None


def test_forc_data_set_gives_the_tabulated_loops_and_reports_the_stress_clamp(forc_file):
    report = loops_main(125e6, BANDS, model_path=forc_file, as_json=True)
    for r in report["loops"]:
        hi, lo = r["band_C"][1], r["band_C"][0]
        assert r["peak_to_peak"] == pytest.approx(float(WIRE.F(hi, lo, 125e6)), rel=1e-9)
    clamped = loops_main(155e6, BANDS, model_path=forc_file, as_json=True)
    assert len(clamped["warnings"]) == 1 and "clamped to 1.45e+08 Pa" in clamped["warnings"][0]
    assert clamped["loops"][0]["peak_to_peak"] == pytest.approx(float(WIRE.F(130, 30, 145e6)))


def test_wire_parameter_file_as_model():
    text = loops_main(155e6, ["60:85"], model_path=DEFAULT_PARAMS)
    assert "reference wire" in text and "2.04 %" in text


@pytest.mark.parametrize("kwargs, message", [
    ({"bands": ["60-85"]}, "T_lo:T_hi"),
    ({"bands": ["85:60"]}, "T_lo < T_hi"),
    ({"bands": ["20:100"]}, "within the model's 30..130 C"),
    ({"stress": float("nan")}, "stress must be"),
    ({"model_path": "no/such/file.csv"}, "cannot read"),
], ids=["malformed", "reversed", "outside", "nan-stress", "missing-file"])
def test_bad_input_is_one_clear_user_error(kwargs, message):
    args = {"stress": 155e6, "bands": ["60:85"], **kwargs}
    with pytest.raises(UserError, match=message):
        loops_main(**args)


def test_parse_band():
    assert parse_band(" 60:90 ") == (60.0, 90.0)
    with pytest.raises(ValueError):
        parse_band("60:nan")
