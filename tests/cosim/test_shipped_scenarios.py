"""musclesim.cosim.scenario_files' shipped scenarios: the package musclesim.scenarios is the
repository's scenarios/ (under this editable install), and `locate` finds a scenario there by its
name where no file of that name exists; a user's own file always wins."""
from pathlib import Path

import pytest

from musclesim.cosim import locate_scenario, shipped_scenarios
from musclesim.errors import UserError

from conftest import ROOT, SCENARIOS


def test_the_shipped_scenarios_are_the_repositorys_folder():
    assert shipped_scenarios() == SCENARIOS
    assert (shipped_scenarios() / "crawler-ideal.toml").is_file()


@pytest.mark.parametrize("name", ["crawler-ideal", "crawler-ideal.toml"], ids=["bare", "suffix"])
def test_a_bare_name_is_the_shipped_scenario_absolute_outside_the_clone(name, tmp_path,
                                                                        monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert locate_scenario(name) == SCENARIOS / "crawler-ideal.toml"


def test_a_shipped_scenario_under_the_current_folder_is_named_relative_to_it(monkeypatch):
    monkeypatch.chdir(ROOT)
    assert locate_scenario("sma-drift") == Path("scenarios/sma-drift.toml")


def test_an_existing_file_wins_over_a_shipped_name(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    Path("crawler-ideal.toml").write_text("# the user's own\n")
    assert locate_scenario("crawler-ideal.toml") == Path("crawler-ideal.toml")
    own = tmp_path / "mine" / "crawler-ideal.toml"
    own.parent.mkdir()
    own.write_text("# the user's own\n")
    assert locate_scenario(own) == own


def test_a_path_with_a_folder_is_never_a_name(tmp_path, monkeypatch):
    """A missing file in a folder stays as given: loading it says it does not exist."""
    monkeypatch.chdir(tmp_path)
    assert locate_scenario("elsewhere/crawler-ideal.toml") == Path("elsewhere/crawler-ideal.toml")


def test_an_unknown_name_is_refused_with_the_nearest_shipped_names(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(UserError) as near:
        locate_scenario("crawler-idael")
    assert str(near.value).startswith("scenario crawler-idael is neither a file nor the name of "
                                      "a shipped scenario; the nearest shipped ones are "
                                      "crawler-ideal")
    with pytest.raises(UserError, match=f"the shipped ones are the files in {SCENARIOS}$"):
        locate_scenario("zzzz")
