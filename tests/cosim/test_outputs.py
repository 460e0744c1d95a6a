"""musclesim.cosim.outputs: output paths refused before the work, files and archives replaced
whole (a reader sees the old one or the new one, never a part), long signals' plotted envelope."""
import zipfile

import numpy as np
import pytest

from musclesim.cosim import (check_archive, check_output_dir, check_output_file, envelope,
                             replace_file, replace_zip)
from musclesim.errors import UserError


def test_an_output_folder_that_is_a_file_and_a_file_that_is_a_folder_are_refused(tmp_path):
    (tmp_path / "f").write_text("x")
    with pytest.raises(UserError, match=r"--out .*f is a file, not a folder"):
        check_output_dir(tmp_path / "f")
    with pytest.raises(UserError, match=r"--report .* is a folder, not a file"):
        check_output_file(tmp_path, "--report")
    with pytest.raises(UserError, match=r"cannot be written: .*f is a file, not a folder"):
        check_output_file(tmp_path / "f" / "deeper" / "out.csv")
    check_output_dir(tmp_path / "new" / "folder")  # to be made: fine
    assert not (tmp_path / "new").exists()  # checking makes nothing


def test_replace_file_writes_whole_files_and_makes_the_folder(tmp_path):
    path = tmp_path / "sub" / "a.json"
    replace_file(path, "one\n")
    replace_file(path, b"two\n")
    assert path.read_bytes() == b"two\n"
    assert sorted(p.name for p in path.parent.iterdir()) == ["a.json"]  # no temporary left


def test_a_failed_archive_leaves_the_old_one_and_no_part(tmp_path):
    path = tmp_path / "x.ssp"
    replace_zip(path, lambda archive: archive.writestr("a.txt", "old"))

    def broken(archive):
        archive.writestr("a.txt", "new")
        raise RuntimeError("disk full")

    with pytest.raises(RuntimeError):
        replace_zip(path, broken)
    with zipfile.ZipFile(path) as zf:
        assert zf.read("a.txt") == b"old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.ssp"]


def test_an_archive_needs_its_suffix_and_a_file_name(tmp_path):
    assert check_archive(str(tmp_path / "a.fmu"), ".fmu", "the FMU") == tmp_path / "a.fmu"
    with pytest.raises(UserError, match="the FMU .*a.zip must have a name ending in .fmu"):
        check_archive(tmp_path / "a.zip", ".fmu", "the FMU")
    (tmp_path / "b.fmu").mkdir()
    with pytest.raises(UserError, match="names a folder, not a file"):
        check_archive(tmp_path / "b.fmu", ".fmu", "the FMU")


def test_a_plotted_envelope_keeps_every_peak():
    t = np.arange(100003) * 4e-4
    y = np.sin(t) + (np.arange(t.size) == 54321) * 5.0  # one spike of a single sample
    tt, yy = envelope(t, y, 1000)
    assert len(yy) == 2 * 1000 + 3 and np.all(np.diff(tt) >= 0)  # min, max per run + the rest
    assert yy.max() == y.max() and yy.min() == y.min() and tt[np.argmax(yy)] <= t[54321]
    np.testing.assert_array_equal(envelope(t[:10], y[:10], 1000)[1], y[:10])  # short
