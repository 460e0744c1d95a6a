"""What a set of predictions is computed from (scenarios/predictions/<name>.toml): the fit whose
values the scenarios ship, the alternative models the diagnosis fitted, the scenarios whose
outcomes are predicted and the study's values our docs give; and the fingerprint of every input.

The format (§predictions says what is made of it)::

    description = "..."
    reference = "§study-outcomes"
    scenarios = ["sma-multiplier-bang-bang", ...]      # every metric of each is predicted

    [fit]                                   # the fit the scenarios ship
    data_set = "study-fast-actuation"       # a folder of scenarios/data
    shipped = [13.9, 0.006, 5.77, 1.69, 16.5]   # per [[calibrate]] table, the value shipped

    [[alternatives]]                        # a model of the diagnosis: a data set fitted with
    name = "supply resistance"              # its [[calibrate]] tables and these opened too
    data_set = "study-fast-actuation-joint"
    open = [{ set = ["mult.source_resistance"], bounds = [0.0, 3.0], why = "..." }]

    [study.sma-multiplier-bang-bang]        # the study's values, by scenario and metric
    multiplier_p2p = 500e-6
"""
from __future__ import annotations

import ast
import hashlib
import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from musclesim.cosim import ParamRef, locate_scenario, shipped_scenarios, source_digest
from musclesim.errors import UserError

_KEYS = {"description", "reference", "scenarios", "fit", "alternatives", "study"}
# the modules whose code makes the predictions (this package), and the diagnosis, whose
# calibrate fits the alternatives: a change of either is a change of the predictions' method
_METHOD = ("prediction", "diagnosis")


@dataclass(frozen=True)
class Opened:
    """A value an alternative model opens besides its data set's own: one value for every
    parameter of `targets`, within (`lower`, `upper`), and `why`."""

    targets: tuple[ParamRef, ...]
    lower: float
    upper: float
    why: str = ""


@dataclass(frozen=True)
class Alternative:
    """An alternative model: data set `data_set` (a folder of scenarios/data) fitted by
    `musclesim calibrate` with its own open values and those of `opened`, named `name`."""

    name: str
    data_set: str
    opened: tuple[Opened, ...] = ()


@dataclass(frozen=True)
class Declaration:
    """A checked declaration read from `path` (see the module docstring)."""

    path: Path
    description: str
    reference: str
    scenarios: tuple[str, ...]
    fit_data_set: str
    shipped: tuple[float, ...]
    alternatives: tuple[Alternative, ...]
    study: dict[str, dict[str, float]]

    @property
    def name(self) -> str:
        """The set's name: its file's stem."""
        return self.path.stem


def data_set_dir(name: str) -> Path:
    """The folder of the shipped data set `name` (scenarios/data/`name`)."""
    return shipped_scenarios() / "data" / name


def load(path: str | Path) -> Declaration:
    """Read and check the declaration at `path`.

    Raises
    ------
    UserError
        Naming the file and every problem found (malformed TOML, unknown keys, a data set or
        scenario that is not shipped, bounds that are not a range).
    """
    path = Path(path)
    try:
        raw = tomllib.loads(path.read_text())
    except OSError as exc:
        raise UserError(f"predictions declaration {path}: {exc.strerror}") from None
    except tomllib.TOMLDecodeError as exc:
        raise UserError(f"predictions declaration {path} is not valid TOML: {exc}") from None
    problems: list[str] = [f"unknown key {k!r}" for k in sorted(set(raw) - _KEYS)]
    fit = raw.get("fit", {})
    data_sets = [fit.get("data_set", "")] + [a.get("data_set", "") for a in
                                             raw.get("alternatives", [])]
    problems += [f"data set {d!r} is not a folder of {shipped_scenarios() / 'data'}"
                 for d in dict.fromkeys(data_sets) if not (data_set_dir(str(d)) / "manifest.toml")
                 .is_file()]
    shipped = fit.get("shipped", [])
    if not shipped or not all(isinstance(v, (int, float)) for v in shipped):
        problems.append("[fit] shipped must be a list of numbers, one per [[calibrate]] table of "
                        "its data set")
    scenarios = raw.get("scenarios", [])
    for name in scenarios:
        try:
            locate_scenario(name)
        except UserError:
            problems.append(f"scenario {name!r} is not a shipped scenario")
    alternatives = [_alternative(a, i, problems) for i, a in enumerate(raw.get("alternatives", []))]
    study = raw.get("study", {})
    problems += [f"[study.{s}] names a scenario not in scenarios" for s in study
                 if s not in scenarios]
    if problems:
        raise UserError(f"predictions declaration {path} has {len(problems)} problem(s): "
                        + "; ".join(problems))
    return Declaration(path, raw.get("description", ""), raw.get("reference", ""),
                       tuple(scenarios), fit["data_set"], tuple(float(v) for v in shipped),
                       tuple(alternatives),
                       {s: {m: float(v) for m, v in d.items()} for s, d in study.items()})


def _alternative(raw: dict[str, Any], index: int, problems: list[str]) -> Alternative:
    """The `index`-th ``[[alternatives]]`` table `raw`, its problems appended to `problems`."""
    where = f"[[alternatives]] {raw.get('name', index + 1)!r}"
    opened = []
    for table in raw.get("open", []):
        lower, upper = (table.get("bounds") or [math.nan, math.nan])[:2]
        if not lower < upper:
            problems.append(f"{where}: bounds {table.get('bounds')} are not a range")
        try:
            targets = tuple(ParamRef.parse(t) for t in table.get("set", []))
        except ValueError as exc:
            problems.append(f"{where}: {exc}")
            targets = ()
        if not targets:
            problems.append(f"{where}: open needs set = [\"instance.parameter\", ...]")
        opened.append(Opened(targets, float(lower), float(upper), table.get("why", "")))
    if not raw.get("name"):
        problems.append(f"{where} has no name")
    return Alternative(str(raw.get("name", "")), str(raw.get("data_set", "")), tuple(opened))


def fingerprint(declaration: Declaration) -> str:
    """sha256 of everything the predictions of `declaration` are computed from: the declaration,
    its scenario files (and those they extend), its data sets' manifests, the components'
    sources (`musclesim.cosim.source_digest`, what the FMUs are built from) and the method's
    code (this package and the diagnosis, each module's syntax tree without docstrings, as the
    diagnosis's calibrated sets fingerprint theirs)."""
    h = hashlib.sha256(declaration.path.read_bytes())
    for name in declaration.scenarios:
        for p in _scenario_files(locate_scenario(name)):
            h.update(p.name.encode() + p.read_bytes())
    for d in dict.fromkeys([declaration.fit_data_set]
                           + [a.data_set for a in declaration.alternatives]):
        h.update(d.encode() + (data_set_dir(d) / "manifest.toml").read_bytes())
    h.update(source_digest().encode())
    root = Path(__file__).resolve().parents[1]
    for package in _METHOD:
        for p in sorted((root / package).glob("*.py")):
            h.update(f"{package}/{p.name}".encode() + _code(p).encode())
    return h.hexdigest()


def _scenario_files(path: Path) -> list[Path]:
    """Scenario file `path` and the files it extends or reads parameters from."""
    files = [path]
    raw = tomllib.loads(path.read_text())
    for inst in raw.get("instances", {}).values():
        if isinstance(inst, dict) and "parameters_file" in inst:
            files.append(path.parent / inst["parameters_file"])
    if "extends" in raw:
        files += _scenario_files(path.parent / raw["extends"])
    return files


def _code(path: Path) -> str:
    """The syntax tree of Python module `path` without its docstrings, dumped."""
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if (isinstance(body, list) and body and isinstance(body[0], ast.Expr)
                and isinstance(body[0].value, ast.Constant)
                and isinstance(body[0].value.value, str)):
            node.body = body[1:] or [ast.Pass()]  # type: ignore[attr-defined]
    return ast.dump(tree)
