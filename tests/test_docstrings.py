"""Every public function and method (tests/public_api.py says which) documents each of its
parameters, as python-control's docstrings_test.py asks of its package: named in a numpydoc
"Parameters" section, or, in a short docstring without one, named in backticks (`name`) in its
text. ``*args`` and ``**kwargs`` are documented as such (``*args``, ``**kwargs`` written out).
A method without a docstring of its own is documented by the one it overrides (a slave's
`advance` by `musclesim.fmu.Slave.advance`); ``__init__`` by its own docstring and its class's.
"""
from __future__ import annotations

import inspect
import re
import sys
import types

from public_api import Member, members

SECTION = re.compile(r"^([ \t]*)Parameters[ \t]*\n\1-{3,}[ \t]*\n", re.M)


def documentation(member: Member) -> str:
    """The docstring that documents `member`'s parameters ("" if none)."""
    doc = inspect.getdoc(member.function) or ""
    if member.function.__name__ == "__init__" and member.owner is not None:
        doc = (inspect.getdoc(member.owner) or "") + "\n\n" + doc
    return doc


def listed(doc: str) -> set[str] | None:
    """The names a numpydoc "Parameters" section of `doc` lists ("a, b : float" lists a and b,
    "**kwargs" lists **kwargs), or None if `doc` has no such section."""
    match = SECTION.search(doc)
    if match is None:
        return None
    indent, names = match.group(1), set()
    lines = doc[match.end():].splitlines() + [""]
    for line, after in zip(lines, lines[1:]):
        if not line.strip() or line.startswith(indent + " ") or line.startswith(indent + "\t"):
            continue  # a blank or description line
        if not line.startswith(indent) or re.fullmatch(r"\s*-{3,}\s*", after):
            break  # dedented, or the next section's title: the section ended
        names.update(n.strip() for n in line.split(" :")[0].split(","))
    return names


def undocumented(member: Member) -> list[str]:
    """The parameters of `member` its documentation does not name (self or cls aside)."""
    doc = documentation(member)
    section = listed(doc)
    params = list(inspect.signature(member.function).parameters.values())
    missing = []
    for p in params[1 if member.bound else 0:]:
        name = ("*" if p.kind == p.VAR_POSITIONAL else "**" if p.kind == p.VAR_KEYWORD
                else "") + p.name
        if section is not None:
            if name not in section:
                missing.append(name)
        elif f"`{name}`" not in doc:
            missing.append(name)
    return missing


def problems(found: list[Member]) -> dict[str, list[str]]:
    """{layer: ["module.qualname: undocumented parameters", ...]} of `found`."""
    out: dict[str, list[str]] = {}
    for m in found:
        missing = undocumented(m)
        if missing:
            out.setdefault(m.layer, []).append(f"{m.name}: {', '.join(missing)}")
    return out


def report(found: dict[str, list[str]]) -> str:
    """One message: per layer, how many functions leave parameters undocumented, then each."""
    lines = [f"{layer}: {len(items)} with undocumented parameters"
             for layer, items in found.items()]
    return "\n".join(lines + [i for items in found.values() for i in items])


def test_every_public_function_documents_its_parameters():
    found = problems(members())
    assert not found, report(found)


PLANTED = '''
def short(a, b, *rest, **options):
    """Adds `a` to b, and *rest and **options in passing."""

def short_ok(a, *rest, **options):
    """Adds `a` to `*rest`, with `**options`."""

def sectioned(a, b, c, **options):
    """Does things with `c`.

    Parameters
    ----------
    a, b : float
        The inputs.
    **options
        Passed on.

    Returns
    -------
    c : float
        Named here, not among the parameters.
    """

class Base:
    def advance(self, t, dt):
        """Advance from `t` by `dt`."""

class Thing(Base):
    """A thing of size `size`."""

    def __init__(self, size, colour):
        """Painted `colour`... or not."""

    def advance(self, t, dt):
        pass

    def undocumented(self, x):
        pass
'''


def test_the_check_finds_what_it_looks_for(monkeypatch):
    """Parameters planted undocumented are each named; documented ones are not, whether in a
    Parameters section, in backticks or by the method a method overrides."""
    module = types.ModuleType("musclesim.planted")
    monkeypatch.setitem(sys.modules, module.__name__, module)
    exec(PLANTED, vars(module))
    objects = [("musclesim.planted", vars(module)[n])
               for n in ("short", "short_ok", "sectioned", "Thing")]
    assert problems(members(iter(objects))) == {"musclesim.planted": [
        "musclesim.planted.short: b, *rest, **options",
        "musclesim.planted.sectioned: c",
        "musclesim.planted.Thing.undocumented: x"]}
