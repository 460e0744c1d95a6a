"""The family of crawler bench forms (musclesim.benchmark.family_crawler): balanced causes, every
form drawn and making a bench, our own model a member, a case recorded as a data set."""
import numpy as np
import pytest

from musclesim.benchmark import cases as own
from musclesim.benchmark import family_crawler as fc
from musclesim.benchmark.benches.crawler import Crawler, run
from musclesim.benchmark.recording import write_case
from musclesim.diagnosis import load_dataset

from conftest import SCENARIOS


def test_the_causes_come_in_equal_shares_and_every_form_is_drawn():
    cases = fc.plan(90, 3)
    causes = [c["cause"] for c in cases]
    assert {k: causes.count(k) for k in fc.CAUSES} == dict.fromkeys(fc.CAUSES, 10)
    for sub, options in fc.FORMS.items():
        assert {c["forms"][sub] for c in cases} == {*options, fc.MODEL}, sub
        assert len(options) >= 2 and all(len(text) > 10 for text in options.values())
    on_model = [c for c in cases if c["bench"] == fc.OWN_BENCH]
    assert 0 < len(on_model) < 0.3 * len(cases)  # MODEL_SHARE, an eighth
    assert fc.plan(90, 3) == cases and fc.plan(90, 4) != cases  # a seed gives the same cases
    assert {c["form_values"]["video_fps"] for c in cases if "form_values" in c} == set(fc.FPS)


def test_each_case_is_labelled_by_its_hidden_change_and_makes_a_bench():
    for c in fc.plan(45, 5):
        if c["cause"] == fc.CALIBRATION_ONLY:
            assert c["kind"] == "none" and not c["values"]
        elif c["cause"] == fc.TWO_EFFECTS:
            assert len(set(c["pair"])) == 2 and set(c["pair"]) <= set(fc.LIBRARY)
        elif c["cause"] == fc.OUTSIDE_LIBRARY:
            assert c["effect"] in fc.OUTSIDE and c["values"] and c["bench"] == fc.BENCH
        else:
            assert c["effect"] == c["cause"] in fc.LIBRARY and c["values"]
        if c["bench"] == fc.OWN_BENCH:  # our own model: the cause in its FMUs' parameters
            effects = c.get("pair") or ([c["effect"]] if c["kind"] == "effect" else [])
            names = {(i,) if isinstance(i, str) else i for e in effects
                     for i, *_ in own.MAGNITUDES[e]}
            assert {k.split(".")[0] for k in c["values"]} == {i for t in names for i in t}
            continue
        bench = Crawler(**fc.bench_fields(c))  # every case makes a bench, its forms in it
        assert (bench.k3 == 0.0) == (c["forms"]["spring"] == "linear")
        assert bench.video_hold == (c["forms"]["camera"] == "held")


@pytest.mark.parametrize("sub", sorted(fc.FORMS))
def test_every_form_changes_what_the_bench_records(sub):
    """Two seconds of one bench with each form of a subsystem (the others at the default's):
    every form gives another recording."""
    case = next(c for c in fc.plan(9, 11) if c["bench"] == fc.BENCH)
    records = []
    for form in fc.FORMS[sub]:
        fields = {**case["conditions"], "k3": 40.0, "video_noise": 0.0, "sensor_noise": 0.0}
        drawn = fc.form_fields({**{s: next(iter(o)) for s, o in fc.FORMS.items()}, sub: form},
                                np.random.default_rng(1))
        out = run(Crawler(**{**fields, **drawn}), 2.0)
        assert np.all(np.isfinite(out["p_meas"])) and np.all(np.isfinite(out["x"]))
        records.append(np.concatenate([out["p_meas"].ravel() / 1e3, out["x"].ravel() / 1e-3]))
    for i in range(len(records)):
        for j in range(i):
            assert np.max(np.abs(records[i] - records[j])) > 0.05, (sub, i, j)


def test_a_bench_case_and_a_model_case_are_recorded_as_data_sets(fmu_dir, tmp_path):
    cases = fc.plan(16, 2)
    picked = [next(c for c in cases if c["bench"] == b) for b in (fc.BENCH, fc.OWN_BENCH)]
    for case in picked:
        case = {**case, "duration": 1.0}
        time, cols, stated = fc.record((case, SCENARIOS, fmu_dir))
        assert time[-1] == pytest.approx(1.0) and stated == {}
        folder = tmp_path / case["case"]
        write_case(case, folder, time, cols, None, SCENARIOS)
        ds = load_dataset(folder, fmu_dir=fmu_dir)
        assert ds.scenario_path.stem == fc.SCENARIO
        assert sorted(str(s) for s in ds.outputs) == sorted(fc.SIGNALS)
