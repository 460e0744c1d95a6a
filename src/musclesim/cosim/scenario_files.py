"""A scenario's TOML files: read, merged along ``extends``, their format checked.

A file may ``extends = "other.toml"`` (relative to it): its tables merge key by key onto the
other's, its connections, recorded signals and plots are added to the other's, its other values
replace them. ``format = 2`` (`FORMAT`) declares that a file uses the port names of the Modelica
Standard Library; a format-1 file may use none of the names format 2 changed
(`musclesim.components.RENAMED`). `musclesim.cosim.scenario` parses the merged table.

The scenarios shipped with musclesim are package data (``musclesim.scenarios``: the repository's
scenarios/ folder, installed with the package); `locate` finds one by its name where a file of
that name does not exist.
"""
from __future__ import annotations

from collections.abc import Iterable, Mapping
import difflib
from pathlib import Path
import tomllib
from typing import Any

from musclesim.components import renamed
from musclesim.cosim.address import Signal
from musclesim.errors import UserError

FORMAT = 2  # the scenario and data-set format written now: the ports' MSL names
_ADDED = ("connections", "record", "plots")  # lists an extending file adds to


def read(path: Path, chain: tuple[Path, ...] = ()) -> dict[str, Any]:
    """The scenario file's table at `path`, merged onto the file it ``extends`` (tables merge
    key by key, connections, recorded signals and plots are added, other values replace);
    `chain` holds the files that extend this one."""
    if path in chain:
        loop = " -> ".join(map(str, chain))
        raise UserError(f"scenario {chain[0]} extends itself through {loop}")
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise UserError(f"scenario {chain[-1]} extends {path}, which cannot be read: {exc}") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise UserError(f"scenario file {path} is not valid TOML: {exc}") from None
    base = data.pop("extends", None)
    fmt = data.pop("format", 1)
    if problem := format_problem(fmt):
        raise UserError(f"scenario {path}: {problem}")
    if base is not None and not isinstance(base, str):
        raise UserError(f"scenario {path}: extends must be a file name, not {base!r}")
    merged = data if base is None else _merge(read(path.parent / base, (*chain, path)), data)
    if fmt < 2:
        _old_names(path, data, merged)
    return merged


def shipped_dir() -> Path:
    """The folder of the scenarios shipped with musclesim: the clone's scenarios/ under an
    editable install, the installed package's ``musclesim/scenarios`` otherwise."""
    import musclesim.scenarios

    return Path(musclesim.scenarios.__file__).parent


def locate(scenario: str | Path) -> Path:
    """The scenario file `scenario` names: a file that exists, as given (a user's own file always
    wins); else, for a bare name without a folder (``.toml`` optional), the shipped scenario of
    that name (`shipped_dir`), as a path relative to the current folder when it lies there.

    Parameters
    ----------
    scenario : str or Path
        A scenario or sweep file, or the name of a shipped one.

    Returns
    -------
    Path

    Raises
    ------
    UserError
        For a bare name that is no file and no shipped scenario, naming the nearest shipped ones;
        a path with a folder is returned as given (loading it says what is wrong with it).

    Examples
    --------
    >>> locate("crawler-ideal").name
    'crawler-ideal.toml'
    """
    path = Path(scenario)
    if path.exists() or len(path.parts) != 1 or path.name in ("", ".", ".."):
        return path
    name = path.name.removesuffix(".toml")
    shipped = shipped_dir()
    found = shipped / f"{name}.toml"
    if found.is_file():
        return found.relative_to(Path.cwd()) if found.is_relative_to(Path.cwd()) else found
    names = sorted(p.stem for p in shipped.glob("*.toml"))
    nearest = difflib.get_close_matches(name, names, n=3, cutoff=0.6)
    hint = (f"the nearest shipped ones are {', '.join(nearest)}" if nearest else
            f"the shipped ones are the files in {shipped}")
    raise UserError(f"scenario {scenario} is neither a file nor the name of a shipped scenario; "
                    + hint)


def _signals(data: Mapping[str, Any]) -> list[Signal]:
    """The signals a scenario file's table names (the strings that parse as one)."""
    def strings(items: object) -> list[str]:
        return [s for s in items if isinstance(s, str)] if isinstance(items, list) else []
    out = strings(data.get("record"))
    for pair in data.get("connections", []) if isinstance(data.get("connections"), list) else ():
        out += strings(pair)
    metrics = data.get("metrics")
    for spec in metrics.values() if isinstance(metrics, dict) else ():
        out += strings([spec.get("signal"), spec.get("over")] if isinstance(spec, dict) else [])
    for panel in data.get("plots", []) if isinstance(data.get("plots"), list) else ():
        out += strings(panel.get("signals") if isinstance(panel, dict) else None)
    signals = []
    for text in out:
        try:
            signals.append(Signal.parse(text))
        except ValueError:  # refused with the scenario's other problems
            continue
    return signals


def format_problem(value: object) -> str | None:
    """What is wrong with a file's ``format`` = `value` (a whole number from 1 to `FORMAT`), or
    None."""
    if not isinstance(value, int) or isinstance(value, bool) or not 1 <= value <= FORMAT:
        return f"format = {value!r} is not one this musclesim reads (1 to {FORMAT})"
    return None


def renamed_signals(signals: Iterable[Signal], components: Mapping[str, str]
                    ) -> dict[Signal, Signal]:
    """{signal: its name since format 2} of the `signals` that name a port format 2 renamed;
    `components` maps instance names to their component's."""
    out = {}
    for signal in signals:
        inst, var = signal.instance, signal.variable
        now = renamed(components[inst], var) if inst in components else None
        if now:
            out[signal] = Signal(inst, now)
    return out


def _old_names(path: Path, data: Mapping[str, Any], merged: Mapping[str, Any]) -> None:
    """Refuse the names format 2 changed in the format-1 file at `path` (its table `data`; the
    instances are those of `merged`, its chain): the PID's y then meant another variable."""
    instances = merged.get("instances")
    components = {name: spec["component"] for name, spec in
                  (instances.items() if isinstance(instances, dict) else ())
                  if isinstance(spec, dict) and isinstance(spec.get("component"), str)}
    problems = [f"{str(signal)!r} is {now} now" for signal, now in
                renamed_signals(dict.fromkeys(_signals(data)), components).items()]
    if problems:
        raise UserError(f"scenario {path} names ports as before format 2 (the Modelica Standard "
                        "Library's port names): " + "; ".join(problems)
                        + "; write the new names and format = 2 at the top of the file")


def _merge(base: dict[str, Any], data: Mapping[str, Any]) -> dict[str, Any]:
    out = dict(base)
    for key, value in data.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = _merge(out[key], value)
        elif key in _ADDED and isinstance(value, list) and isinstance(out.get(key), list):
            out[key] = out[key] + value
        else:
            out[key] = value
    return out
