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
    # every module of every layer and component ships: pyproject's package list misses none
    sources = {f"musclesim/{p.relative_to(ROOT / 'src' / 'musclesim')}"
               for p in (ROOT / "src" / "musclesim").rglob("*.py")}
    sources |= {f"musclesim/components/{p.relative_to(ROOT / 'components')}"
                for p in (ROOT / "components").rglob("*.py")}
    assert "musclesim/cosim/master.py" in sources
    assert sorted(sources - set(names)) == []
    entry_points = zipfile.ZipFile(wheel).read(
        next(n for n in names if n.endswith("entry_points.txt"))).decode()
    assert "musclesim = musclesim.cli:main" in entry_points
