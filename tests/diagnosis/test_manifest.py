"""The data-set format's checks (musclesim.diagnosis.manifest): every kind of mistake in
manifest.toml and data.csv is reported, all at once, naming the file and where in it."""
import pytest

from musclesim.diagnosis import dataset

from dataset_files import (COLUMNS, GOOD_MANIFEST, REAL, SCALAR, good_rows, problems_of,
                           replace_in_good, rows_with, write_set)


# id -> (manifest, header, rows, expected fragment of the message)
CASES = {
    "malformed-toml": (GOOD_MANIFEST + "oops = \n", None, None,
                       "manifest.toml is not valid TOML"),
    "unknown-key": (GOOD_MANIFEST.replace("description", "descripton"), None, None,
                    "unknown key 'descripton'"),
    "missing-column": (replace_in_good('outputs = ["body.x_cm"]', 'outputs = ["body.x_cm", "body.v"]'),
                       None, None, "column 'body.v' is missing from data.csv"),
    "unknown-column": (None, ("time", *COLUMNS, "body.extra"),
                       [r + [1.0] for r in good_rows()],
                       "data.csv: column 'body.extra' is in neither inputs nor outputs"),
    "duplicated-column": (None, ("time", "inputs.f_a", "body.x_cm", "body.x_cm"),
                          [r + [1.0] for r in good_rows()], "column 4: 'body.x_cm' appears twice"),
    "bad-column-name": (None, ("time", "inputs.f_a", "x_cm"), None,
                        "'x_cm' is not of the form instance.variable"),
    "first-not-time": (None, ("t", *COLUMNS), None, "the first column must be 'time'"),
    "field-count": (None, None, good_rows()[:3] + [[0.3, 1.0]] + good_rows()[4:],
                    "data.csv line 5: 2 fields where the header has 3"),
    "not-a-number": (None, None, rows_with(2, 1, "abc"),
                     "data.csv line 4, column 'inputs.f_a': 'abc' is not a number"),
    "nan": (None, None, rows_with(3, 2, "nan"),
            "data.csv line 5, column 'body.x_cm': nan is not finite"),
    "inf": (None, None, rows_with(3, 1, "inf"),
            "data.csv line 5, column 'inputs.f_a': inf is not finite"),
    "duplicated-time": (None, None, rows_with(4, 0, 0.3), "data.csv line 6: time repeats"),
    "decreasing-time": (None, None, rows_with(4, 0, 0.25),
                        "data.csv line 6: time decreases (0.3 then 0.25 s)"),
    "span-outside": (replace_in_good("span = [0.5, 0.9]", "span = [0.5, 2.0]"), None, None,
                     "experiment 'second': span [0.5, 2.0] s is outside the data [0.0, 0.9] s"),
    "span-malformed": (replace_in_good("span = [0.5, 0.9]", "span = [0.9, 0.5]"), None, None,
                       "span [0.9, 0.5] is not [t0, t1] with t0 < t1"),
    "overlap": (replace_in_good("span = [0.5, 0.9]", "span = [0.4, 0.9]"), None, None,
                "experiments 'first' [0.0, 0.5] and 'second' [0.4, 0.9] overlap"),
    "split-unknown": (replace_in_good('held_out = ["second"]', 'held_out = ["third"]'), None, None,
                      "held_out names unknown experiment 'third'"),
    "split-empty": (replace_in_good('held_out = ["second"]', 'held_out = ["first", "second"]'), None,
                    None, "the train part is empty"),
    "split-missing": (GOOD_MANIFEST.split("[split]")[0], None, None, "no [split] table"),
    "fraction-too-big": (replace_in_good('held_out = ["second"]', "held_out_fraction = 0.99"), None,
                         None, "leaves the train part of experiment 'first' with fewer"),
    "bad-uncertainty": (replace_in_good("uncertainty = 0.001", "uncertainty = -1"), None, None,
                        "metric 'mean_speed': uncertainty -1 is not a finite number >= 0"),
    "no-data-but-columns": (None, None, False, "data.csv is missing but manifest.toml lists"),
}


@pytest.mark.parametrize("case", CASES, ids=list(CASES))
def test_each_error_kind_is_reported(tmp_path, case):
    manifest, header, rows, expected = CASES[case]
    folder = write_set(tmp_path / "set", manifest or GOOD_MANIFEST,
                       header or ("time", *COLUMNS), rows)
    message = problems_of(folder)
    assert message.startswith(f"data set {folder} has ")
    assert expected in message


def test_missing_manifest_and_folder(tmp_path):
    (tmp_path / "empty").mkdir()
    assert "manifest.toml is missing" in problems_of(tmp_path / "empty")
    assert "is not a directory" in problems_of(tmp_path / "nowhere")


def test_many_problems_come_together_in_one_message(tmp_path):
    rows = good_rows()
    rows[2][2] = "nan"
    rows[6][0] = 0.45
    manifest = replace_in_good('held_out = ["second"]', 'held_out = ["third"]').replace(
        '"body.x_cm" = "m"', '"body.y" = "m"')
    folder = write_set(tmp_path / "set", manifest, rows=rows)
    message = problems_of(folder)
    expected = ["data.csv line 4, column 'body.x_cm'", "data.csv line 8: time decreases",
                "[units] names 'body.y'", "unknown experiment 'third'"]
    for fragment in expected:
        assert fragment in message
    assert f"has {len(expected)} problem(s)" in message
    assert "\n" not in message


def test_scalar_only_needs_metrics_and_no_time_split(tmp_path):
    manifest = ('scenario = "crawler-ideal"\n[experiments.a]\n[experiments.b]\n'
                'metrics.v = { value = "fast" }\n[split]\nheld_out_fraction = 0.5\n')
    message = problems_of(write_set(tmp_path / "set", manifest, rows=False))
    assert "experiment 'a': no metrics" in message
    assert "metric 'v': needs value = a finite number" in message
    assert "held_out_fraction needs time series" in message


def test_scalar_only_experiments_may_shorten_the_model_run(tmp_path):
    ds = dataset.load(REAL)
    assert {e.stop_time for e in ds.experiments.values()} == {12.0}
    manifest = ('scenario = "crawler-ideal"\n[experiments.a]\nstop_time = -1\n'
                'metrics.mean_speed = { value = 0.02, unit = "m/s" }\n')
    assert "experiment 'a': stop_time -1 is not a positive number of seconds" in problems_of(
        write_set(tmp_path / "scalar", manifest, rows=False))
    timed = GOOD_MANIFEST.replace("[experiments.first]\n", "[experiments.first]\nstop_time = 3\n")
    assert "stop_time 3 is for scalar-only sets" in problems_of(write_set(tmp_path / "ts", timed))


def test_bad_open_values_are_reported(tmp_path):
    manifest = SCALAR + ('[[calibrate]]\nset = ["k"]\nbounds = [1.0, 2.0]\n'
                         '[[calibrate]]\nset = ["body.k"]\nbounds = [2.0, 1.0]\n'
                         '[[calibrate]]\nset = ["body.c"]\nbounds = [1.0, 2.0]\nstep = 1\n'
                         '[[calibrate]]\nset = ["body.c"]\nbounds = [1.0, 3.0]\n')
    manifest = manifest.replace('conditions = { "body.k" = 210.0 }',
                                'conditions = { "body.k" = "stiff" }')
    message = problems_of(write_set(tmp_path / "set", manifest, rows=False))
    assert "[[calibrate]] 1: set must list one or more \"instance.parameter\" names" in message
    assert "[[calibrate]] 2: bounds [2.0, 1.0] is not [lower, upper] with lower < upper" in message
    assert "[[calibrate]] 3: unknown key 'step'" in message
    assert "[[calibrate]]: 'body.c' is in more than one set" in message
    assert "experiment 'a': [conditions] 'body.k' must be a finite number" in message
