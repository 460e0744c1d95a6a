"""musclesim.batch.plugins: a worker writes shipped FMUs into a folder of its own and finds them
by key, refuses FMUs built from other sources, and removes them as it goes."""
import os
from pathlib import Path
from types import SimpleNamespace

import pytest

from musclesim.batch import FmuFolder
from musclesim.batch.plugins import ShippedFmus
from musclesim.batch.shipped import FOLDERS, folder_files
from musclesim.errors import UserError


def test_shipped_fmus_are_found_by_key_and_removed_on_teardown(fmu_dir, tmp_path):
    worker = SimpleNamespace(address="tcp://w1", local_directory=str(tmp_path))
    plugin = ShippedFmus("k-plugin", folder_files(fmu_dir, ["SignalSource"]))
    plugin.setup(worker)
    folder = Path(os.fspath(FmuFolder("k-plugin")))
    assert folder.parent == tmp_path
    assert sorted(p.name for p in folder.iterdir()) == ["BUILD.json", "SignalSource.fmu"]
    plugin.teardown(worker)
    assert "k-plugin" not in FOLDERS and not folder.exists()


def test_fmus_from_other_sources_are_refused_and_not_kept(fmu_dir, tmp_path):
    files = folder_files(fmu_dir, ["SignalSource"])
    files["BUILD.json"] = b'{"musclesim": "0.0-other", "sources": "other", "fmus": {}}'
    worker = SimpleNamespace(address="tcp://w2", local_directory=str(tmp_path))
    with pytest.raises(UserError, match=r"Dask worker tcp://w2 runs other musclesim sources than "
                                        r"the FMUs were built from \(musclesim 0.0-other\)"):
        ShippedFmus("k-other", files).setup(worker)
    assert "k-other" not in FOLDERS and list(tmp_path.iterdir()) == []
