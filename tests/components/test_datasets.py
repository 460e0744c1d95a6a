"""The hysteresis data sets (components/sma/datasets.py): the root an FMU ships, the index of FORC
data sets and its errors, surfaces by id built once and shared, the single-surface stress."""
import shutil
from pathlib import Path

import pytest

from musclesim.components.sma import datasets


def test_the_root_is_the_package_or_the_fmus_resources():
    assert datasets.shipped(None) == datasets.PACKAGE_DIR
    assert datasets.shipped("/x/resources") == Path("/x/resources/musclesim/components/sma")


def test_the_index_lists_the_shipped_sets_by_id():
    sets = datasets.forc_sets()
    assert sorted(sets)[:2] == [1, 2] and all(path.is_file() for path, _ in sets.values())


@pytest.mark.parametrize("index, match", [
    ("[sets.0]\nfile = 'a.csv'\n", r"entry \[sets.0\] needs a positive integer id"),
    ("[sets.x]\nfile = 'a.csv'\n", r"entry \[sets.x\]"), ("[sets.1]\n", r"entry \[sets.1\]"),
    ("[sets.1\n", "cannot read the FORC data set index")])
def test_a_bad_index_names_itself_and_the_entry(tmp_path, index, match):
    (tmp_path / "data").mkdir()
    (tmp_path / "data" / "forc-sets.toml").write_text(index)
    with pytest.raises(ValueError, match=match):
        datasets.forc_sets(tmp_path)


def test_surfaces_by_id_are_built_once_and_shared():
    full = datasets.surface(1)
    assert datasets.surface(1.0) is full and len(full.stresses) == 5
    one = datasets.surface(1, 120e6)
    assert one.stresses.tolist() == [120e6] and datasets.surface(1, 120e6) is one
    assert one.F(100.0, 40.0, 0.0) == pytest.approx(full.F(100.0, 40.0, 120e6), rel=1e-12)


def test_the_same_file_under_another_root_is_the_same_surface(tmp_path):
    root = tmp_path / "sma"
    shutil.copytree(datasets.PACKAGE_DIR / "data", root / "data")
    assert datasets.surface(1, root=root) is datasets.surface(1)


@pytest.mark.parametrize("k, sigma, match", [
    (-1, 0.0, "hysteresis must be 0"), (1.5, 0.0, "hysteresis must be 0"),
    (99, 0.0, "hysteresis = 99 is no data set"), (1, 50e6, "sigma_surface must be 0")])
def test_bad_ids_and_stresses_name_the_parameter(k, sigma, match):
    with pytest.raises(ValueError, match=match):
        datasets.surface(k, sigma)
