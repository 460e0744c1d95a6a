"""The predictions' declarations (scenarios/predictions/*.toml) and the shipped predictions they
make: the shipped ones are their inputs' own (a fingerprint, never recomputed here), and a bad
declaration is refused in one sentence."""
import json

import pytest

from musclesim.cosim import load_scenario, locate_scenario
from musclesim.diagnosis import load_dataset
from musclesim.errors import UserError
from musclesim.prediction import fingerprint, folder, load_declaration, made_for
from musclesim.prediction.declaration import data_set_dir

DECLARATIONS = sorted(folder().glob("*.toml"))


def test_a_set_of_predictions_ships():
    assert [p.name for p in DECLARATIONS] == ["fast-actuation.toml"]


@pytest.mark.parametrize("path", DECLARATIONS, ids=lambda p: p.stem)
def test_the_shipped_predictions_are_their_inputs_own(path):
    """Fails when a scenario file, a data set's manifest, a component's source, the diagnosis or
    this package changed since the predictions were computed: recompute them with `musclesim
    predict scenarios/predictions/fast-actuation.toml --out
    scenarios/predictions/fast-actuation.json --workers 1` (about 4 minutes on two cores)."""
    declaration = load_declaration(path)
    doc = json.loads(path.with_suffix(".json").read_text())
    assert doc["fingerprint"] == fingerprint(declaration), (
        f"the inputs of {path.name} changed since its predictions were computed: recompute them "
        "(see docstring)")
    assert list(doc["scenarios"]) == list(declaration.scenarios)
    for name, entry in doc["scenarios"].items():
        s = load_scenario(locate_scenario(name))
        assert entry["made_for"] == json.loads(json.dumps(made_for(s)))
        assert list(entry["outcomes"]) == list(s.metrics)


def test_the_fingerprint_follows_the_declaration(tmp_path):
    declaration = load_declaration(DECLARATIONS[0])
    copy = tmp_path / "copy.toml"
    copy.write_text(DECLARATIONS[0].read_text().replace("16.5]", "16.4]"))
    assert fingerprint(load_declaration(copy)) != fingerprint(declaration)


def test_the_study_s_values_are_those_of_the_data_sets():
    """Every study value a declaration gives is a measured metric of an experiment of that
    scenario in one of its data sets (no second copy that could drift)."""
    declaration = load_declaration(DECLARATIONS[0])
    measured: dict = {}
    for name in {declaration.fit_data_set, *(a.data_set for a in declaration.alternatives)}:
        for e in load_dataset(data_set_dir(name)).experiments.values():
            for m, mm in e.metrics.items():
                measured.setdefault((e.scenario, m), set()).add(mm.value)
    for scenario, values in declaration.study.items():
        for metric, value in values.items():
            assert value in measured[(scenario, metric)], (scenario, metric)


def test_a_bad_declaration_names_its_file_and_every_problem(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('scenarios = ["no-such-scenario"]\nwhat = 1\n[fit]\ndata_set = "nothing"\n'
                   'shipped = []\n[[alternatives]]\nname = "x"\ndata_set = "nothing"\n'
                   'open = [{ set = ["a.b"], bounds = [2.0, 1.0] }]\n')
    with pytest.raises(UserError) as exc:
        load_declaration(bad)
    text = str(exc.value)
    assert text.startswith(f"predictions declaration {bad} has 5 problem(s)")
    for part in ("unknown key 'what'", "data set 'nothing'", "[fit] shipped",
                 "scenario 'no-such-scenario'", "bounds [2.0, 1.0] are not a range"):
        assert part in text
