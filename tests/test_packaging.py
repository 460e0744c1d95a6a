"""The release: `python -m build` makes an sdist and a wheel that install only under the
`musclesim` name, with its console script, every module, the shipped scenarios with their
parameter files and data sets, LICENSE, py.typed and metadata that says what the package does;
the version is written once (musclesim.__version__). Installing the wheel in a clean venv and
running a shipped scenario takes minutes: `.ci/wheel` does it in CI, not this suite."""
import email.parser
import subprocess
import sys
import tarfile
import tomllib
import zipfile

import pytest

import musclesim
from conftest import ROOT, SCENARIOS

VERSION = musclesim.__version__
# the repository's scripts in scenarios/ that write data sets: in the sdist, not the wheel
SCRIPTS = {"data/make_examples.py"}


@pytest.fixture(scope="module")
def dist(tmp_path_factory):
    """The folder `python -m build` wrote the sdist and the wheel into: the wheel built from the
    sdist, as a release makes it (so the sdist is whole, and no file left in the clone's build/
    by an earlier build slips into the wheel)."""
    out = tmp_path_factory.mktemp("dist")
    subprocess.run([sys.executable, "-m", "build", "-o", str(out), str(ROOT)], check=True,
                   capture_output=True)
    return out


@pytest.fixture(scope="module")
def wheel(dist):
    (path,) = dist.glob("musclesim-*.whl")
    return zipfile.ZipFile(path)


@pytest.fixture(scope="module")
def metadata(wheel):
    text = wheel.read(f"musclesim-{VERSION}.dist-info/METADATA").decode()
    return email.parser.Parser().parsestr(text)


def shipped_data():
    """The shipped scenarios' files (scenarios, parameter files, data sets), relative to
    scenarios/: what the wheel carries as package data of musclesim.scenarios."""
    return {p.relative_to(SCENARIOS).as_posix() for p in SCENARIOS.rglob("*")
            if p.is_file() and "__pycache__" not in p.parts and p.suffix != ".py"}


def test_wheel_holds_only_musclesim_packages(wheel):
    names = wheel.namelist()
    tops = {n.split("/")[0] for n in names}
    assert tops == {"musclesim", f"musclesim-{VERSION}.dist-info"}
    # every module of every layer and component ships: pyproject's package list misses none
    sources = {f"musclesim/{p.relative_to(ROOT / 'src' / 'musclesim')}"
               for p in (ROOT / "src" / "musclesim").rglob("*.py")}
    sources |= {f"musclesim/components/{p.relative_to(ROOT / 'components')}"
                for p in (ROOT / "components").rglob("*.py")}
    assert "musclesim/cosim/master.py" in sources
    assert sorted(sources - set(names)) == []
    entry_points = wheel.read(f"musclesim-{VERSION}.dist-info/entry_points.txt").decode()
    assert "musclesim = musclesim.cli:main" in entry_points


def test_wheel_carries_the_shipped_scenarios_their_parameters_and_data_sets(wheel):
    data = shipped_data()
    assert {"crawler-ideal.toml", "params/sma-thermal-gains.toml",
            "data/sma-stress-ignored/manifest.toml", "data/sma-stress-ignored/data.csv",
            "data/crawler-real/manifest.toml"} <= data
    in_wheel = {n.removeprefix("musclesim/scenarios/") for n in wheel.namelist()
                if n.startswith("musclesim/scenarios/")}
    assert in_wheel == data | {"__init__.py"}
    assert not SCRIPTS & in_wheel


def test_wheel_carries_the_license_py_typed_and_the_components_data(wheel):
    names = set(wheel.namelist())
    assert {f"musclesim-{VERSION}.dist-info/licenses/LICENSE", "musclesim/py.typed",
            "musclesim/components/sma/data/forc-sets.toml",
            "musclesim/schemas/summary.schema.json"} <= names
    license_text = wheel.read(f"musclesim-{VERSION}.dist-info/licenses/LICENSE").decode()
    assert license_text.startswith("MIT License\n\nCopyright (c) 2026 musclesim developers\n")
    assert license_text == (ROOT / "LICENSE").read_text()


def test_metadata_says_what_the_package_does(metadata):
    assert metadata["Name"] == "musclesim" and metadata["Version"] == VERSION
    assert "FMI 2.0 and 3.0 co-simulation" in metadata["Summary"]
    assert metadata["License-Expression"] == "MIT"
    assert metadata["Requires-Python"] == ">=3.11"
    assert {"Programming Language :: Python :: 3.11", "Topic :: Scientific/Engineering",
            "Typing :: Typed"} <= set(metadata.get_all("Classifier"))
    assert metadata.get_payload().startswith("# musclesim\n")  # the README


def test_the_version_is_written_once():
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert "version" not in pyproject["project"] and "version" in pyproject["project"]["dynamic"]
    assert pyproject["tool"]["setuptools"]["dynamic"]["version"] == {
        "attr": "musclesim.__version__"}


def test_sdist_holds_the_sources_scenarios_tests_docs_and_changelog(dist):
    (path,) = dist.glob(f"musclesim-{VERSION}.tar.gz")
    top = f"musclesim-{VERSION}/"
    with tarfile.open(path) as sdist:
        names = {n.removeprefix(top) for n in sdist.getnames()}
    assert {"pyproject.toml", "README.md", "LICENSE", "CHANGELOG.md", "MANIFEST.in", "PKG-INFO",
            "src/musclesim/cosim/master.py", "src/musclesim/py.typed",
            "components/sma/slaves.py", "scenarios/__init__.py", "tests/conftest.py",
            "docs/index.md", "docs/conf.py"} <= names
    assert {f"scenarios/{n}" for n in shipped_data() | SCRIPTS} <= names
    assert not {n for n in names if "__pycache__" in n or n.startswith("docs/_build")}


def test_the_changelog_keeps_a_changelog():
    text = (ROOT / "CHANGELOG.md").read_text()
    assert text.startswith("# Changelog\n")
    assert "https://keepachangelog.com/en/1.1.0/" in text
    assert "\n## [Unreleased]\n" in text
    sections = [line for line in text.splitlines() if line.startswith("### ")]
    assert sections and set(sections) <= {"### Added", "### Changed", "### Deprecated",
                                          "### Removed", "### Fixed", "### Security"}
