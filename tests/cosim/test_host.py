"""musclesim.cosim.host: an FMU archive read as untrusted (entries checked before anything is
written, no DTD), once per file inside `reuse_fmus`; orphaned run folders cleaned up."""
import os
import re
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

import pytest

from musclesim.cosim import read_fmu, reuse_fmus
from musclesim.cosim.host import extract_fmu, extracted_fmu, remove_orphan_runs
from musclesim.errors import UserError


@pytest.mark.parametrize("entry, problem", [
    ("../evil.txt", "leaves the archive's folder ('..')"),
    ("/etc/evil.txt", "has an absolute path"),
])
def test_an_entry_out_of_the_archives_folder_is_refused_and_nothing_written(tmp_path, entry,
                                                                             problem):
    fmu = tmp_path / "bad.fmu"
    with zipfile.ZipFile(fmu, "w") as zf:
        zf.writestr("modelDescription.xml", "<fmiModelDescription/>")
        zf.writestr(entry, "x")
    message = f"FMU {fmu}: entry '{entry}' {problem}, refused"
    with pytest.raises(UserError, match=re.escape(message)):
        extract_fmu(fmu, tmp_path / "out")
    assert not (tmp_path / "out").exists() and not (tmp_path / "evil.txt").exists()


def test_a_description_with_a_dtd_is_refused(tmp_path):
    fmu = tmp_path / "dtd.fmu"
    with zipfile.ZipFile(fmu, "w") as zf:
        zf.writestr("modelDescription.xml", '<!DOCTYPE x [<!ENTITY a "b">]><x/>')
    with pytest.raises(UserError, match="declares a DTD or entities, refused"):
        read_fmu(fmu)


def test_inside_reuse_fmus_a_file_is_read_and_extracted_once(fmu_dir):
    path = fmu_dir / "SignalSource.fmu"
    assert extracted_fmu(path) is None  # outside the block: nothing kept
    with reuse_fmus():
        assert read_fmu(path) is read_fmu(path)
        folder = extracted_fmu(path)
        assert folder == extracted_fmu(path) and Path(folder, "modelDescription.xml").is_file()
    assert not Path(folder).exists()  # removed as the block ends


def test_the_folder_of_a_dead_run_is_removed_and_a_live_ones_kept():
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True).stdout.strip()
    gone = Path(tempfile.mkdtemp(prefix=f"musclesim_run_{dead}_"))
    alive = Path(tempfile.mkdtemp(prefix=f"musclesim_run_{os.getpid()}_"))
    try:
        remove_orphan_runs()
        assert not gone.exists() and alive.exists()
    finally:
        alive.rmdir()
