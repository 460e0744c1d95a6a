"""musclesim.batch.shipped: an FMU folder as bytes for the workers, unpacked by plain file names
only; an `FmuFolder` is a path only where its files were unpacked."""
import json
import os
from pathlib import Path

import pytest

from musclesim.batch import FmuFolder
from musclesim.batch.shipped import FOLDERS, built_version, folder_files, unpack
from musclesim.errors import UserError


def test_folder_files_takes_the_fmus_asked_for_and_build_json(tmp_path):
    for name in ("A.fmu", "B.fmu"):
        (tmp_path / name).write_bytes(name.encode())
    (tmp_path / "BUILD.json").write_text('{"musclesim": "1.2"}')
    assert sorted(folder_files(tmp_path)) == ["A.fmu", "B.fmu", "BUILD.json"]
    files = folder_files(tmp_path, ["B", "C"])  # C is not there: the master names it
    assert sorted(files) == ["B.fmu", "BUILD.json"] and files["B.fmu"] == b"B.fmu"
    assert built_version(files) == "1.2" and built_version({}) is None
    assert built_version({"BUILD.json": b"not json"}) is None


@pytest.mark.parametrize("name", ["../x.fmu", "sub/x.fmu", "..", ""])
def test_unpack_writes_plain_file_names_only(tmp_path, name):
    with pytest.raises(UserError, match="not a plain file name"):
        unpack({name: b"x"}, tmp_path)
    assert list(tmp_path.iterdir()) == []


def test_an_fmu_folder_is_a_path_only_where_it_was_unpacked(tmp_path):
    folder = FmuFolder("k-test")
    with pytest.raises(UserError, match="not unpacked in this process"):
        os.fspath(folder)
    FOLDERS["k-test"] = str(tmp_path)
    try:
        assert Path(folder) == tmp_path and os.fspath(folder) == str(tmp_path)
        assert str(folder) != str(tmp_path)  # its text is not a path
    finally:
        del FOLDERS["k-test"]
    unpack({"A.fmu": b"a", "BUILD.json": json.dumps({"musclesim": "1"}).encode()}, tmp_path)
    assert (tmp_path / "A.fmu").read_bytes() == b"a"
