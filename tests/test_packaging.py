"""The distribution installs only under the `musclesim` name, with its console script."""
import subprocess
import sys
import zipfile

from conftest import ROOT


def test_wheel_holds_only_musclesim_packages(tmp_path):
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(tmp_path),
                    str(ROOT)], check=True)
    (wheel,) = tmp_path.glob("musclesim-*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    tops = {n.split("/")[0] for n in names}
    assert tops == {"musclesim", next(t for t in tops if t.endswith(".dist-info"))}
    assert "musclesim/components/crawler/slaves.py" in names
    assert "musclesim/master.py" in names
    entry_points = zipfile.ZipFile(wheel).read(
        next(n for n in names if n.endswith("entry_points.txt"))).decode()
    assert "musclesim = musclesim.cli:main" in entry_points
