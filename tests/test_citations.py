"""Every citation of the docs (`§label`) in the repository names a section that exists, and no file
cites a document outside the repository (the study's restatement the developers work from)."""
import re
from pathlib import Path

import pytest

from conftest import ROOT

CITATION = re.compile(r"§([a-z][a-z0-9-]*[a-z0-9])")
TARGET = re.compile(r"^\(([a-z][a-z0-9-]*[a-z0-9])\)=\s*$", re.M)
# documents outside the repository; written in pieces so that this file does not cite them
OUTSIDE = re.compile("|".join([r"\.\./" + "shared", r"\b" + "SPEC" + r"\.md\b",
                               r"\b" + "DESIGN" + r"\.md\b", r"\b" + "SPEC" + r" \d"]))
SCANNED = ("README.md", "pyproject.toml", ".ci", "benchmarks", "components", "docs", "scenarios",
           "src", "tests")
SKIPPED = {"_build", "__pycache__", ".pytest_cache", ".hypothesis"}
TEXT = {".py", ".md", ".toml", ".csv", ".json", ".txt", ".cfg", ""}


def files(root=ROOT):
    """The repository's text files that can cite the docs."""
    for top in SCANNED:
        path = root / top
        candidates = [path] if path.is_file() else path.rglob("*")
        for p in candidates:
            if p.is_file() and p.suffix in TEXT and not SKIPPED & set(p.parts):
                yield p


def labels(docs):
    """{label: [files defining it]} of the MyST targets ``(label)=`` under `docs`."""
    found = {}
    for page in Path(docs).rglob("*.md"):
        if "_build" not in page.parts:
            for label in TARGET.findall(page.read_text(encoding="utf-8")):
                found.setdefault(label, []).append(page)
    return found


def problems(paths, defined):
    """Sentences naming each citation of an unknown section and each outside citation
    (``§label`` itself is the notation, not a citation)."""
    out = []
    for path in paths:
        if Path(path).resolve() == Path(__file__).resolve():
            continue  # the checker's own planted examples
        for n, line in enumerate(Path(path).read_text(encoding="utf-8").splitlines(), start=1):
            for label in CITATION.findall(line):
                if label not in defined and label != "label":
                    out.append(f"{path}:{n}: cites §{label}, which no docs page defines")
            if OUTSIDE.search(line):
                out.append(f"{path}:{n}: cites a document outside the repository")
    return out


def test_every_cited_section_exists_and_nothing_outside_is_cited():
    defined = labels(ROOT / "docs")
    assert problems(files(), defined) == []


def test_every_section_is_defined_once_and_the_model_reference_lists_its_labels():
    defined = labels(ROOT / "docs")
    assert {k: v for k, v in defined.items() if len(v) > 1} == {}
    index = (ROOT / "docs" / "model" / "index.md").read_text()
    model = {k for k, v in defined.items() if v[0].parent.name == "model"}
    listed = set(re.findall(r"^\| `§([a-z0-9-]+)` \|", index, re.M))
    assert listed == model - {"model-reference", "citations"}


@pytest.mark.parametrize("text, expected", [
    ("k = 200.0  # N/m (§ideal-actuation)\n", []),
    ("k = 200.0  # N/m (§no-such-section)\n", ["cites §no-such-section"]),
    ("see " + "SPEC" + " 1.4\n", ["outside the repository"]),
    ("see ../" + "shared/" + "SPEC" + ".md\n", ["outside the repository"]),
    ("as " + "DESIGN" + ".md says\n", ["outside the repository"]),
    ("SPECIFIC_HEAT = 837.0\n", []),
])
def test_the_checker_bites(tmp_path, text, expected):
    docs = tmp_path / "docs"
    docs.mkdir()
    (docs / "page.md").write_text("(ideal-actuation)=\n## Ideal actuation\n")
    planted = tmp_path / "code.py"
    planted.write_text(text)
    found = problems([planted], labels(docs))
    assert len(found) == len(expected)
    for sentence, part in zip(found, expected):
        assert part in sentence and "code.py:1" in sentence
