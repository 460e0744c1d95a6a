"""Every public function and method (tests/public_api.py says which) annotates each of its
parameters and its return, and no public dataclass or named tuple types a field ``object``,
``Any`` or a bare container (``tuple``, ``dict``, ``list``, ``set``): the real type belongs in the
annotation, not in a comment. mypy (.ci/mypy) checks that
the annotations hold; this test that they exist, which mypy's settings cannot ask of public names
alone."""
from __future__ import annotations

import dataclasses
import inspect
import sys
import types
from typing import Any

from public_api import Member, classes, members

BARE = (tuple, dict, list, set, frozenset)
VAGUE = {object, Any, *BARE, "object", "Any", "typing.Any", *(t.__name__ for t in BARE)}


def unannotated(member: Member) -> list[str]:
    """The parameters of `member` without an annotation, and "return" if its return has none
    (``__init__`` returns None whatever it says; its self or cls needs none)."""
    signature = inspect.signature(member.function, follow_wrapped=True)
    params = list(signature.parameters.values())[1 if member.bound else 0:]
    missing = [("*" if p.kind == p.VAR_POSITIONAL else "**" if p.kind == p.VAR_KEYWORD else "")
               + p.name for p in params if p.annotation is inspect.Parameter.empty]
    if signature.return_annotation is inspect.Signature.empty \
            and member.function.__name__ != "__init__":
        missing.append("return")
    return missing


def vague_fields(cls: type) -> list[str]:
    """The fields of dataclass or named tuple `cls` typed ``object``, ``Any`` or a bare
    container."""
    if dataclasses.is_dataclass(cls):
        fields = {f.name: f.type for f in dataclasses.fields(cls)}
    elif issubclass(cls, tuple) and hasattr(cls, "_fields"):
        fields = dict(getattr(cls, "__annotations__", {}))
    else:
        return []
    return [name for name, kind in fields.items() if kind in VAGUE]


def problems(found: list[Member], kinds: list[tuple[str, type]]) -> dict[str, list[str]]:
    """{layer: ["module.qualname: what lacks a type", ...]} of `found` and classes `kinds`."""
    out: dict[str, list[str]] = {}
    for m in found:
        missing = unannotated(m)
        if missing:
            out.setdefault(m.layer, []).append(f"{m.name}: {', '.join(missing)}")
    for layer, cls in kinds:
        for name in vague_fields(cls):
            out.setdefault(layer, []).append(f"{cls.__module__}.{cls.__qualname__}.{name}: "
                                             "field typed object, Any or a bare container")
    return out


def report(found: dict[str, list[str]]) -> str:
    """One message: per layer, how many names lack types, then each of them."""
    lines = [f"{layer}: {len(items)} without full annotations" for layer, items in found.items()]
    return "\n".join(lines + [i for items in found.values() for i in items])


def test_every_public_function_and_field_is_fully_annotated():
    found = problems(members(), classes())
    assert not found, report(found)


def test_the_check_finds_what_it_looks_for(monkeypatch):
    """Functions, methods and fields planted without types are each named; typed ones are not."""
    module = types.ModuleType("musclesim.planted")
    monkeypatch.setitem(sys.modules, module.__name__, module)  # dataclasses look it up
    exec('''
import dataclasses
from typing import Any

def bare(a, b: int, *rest, **options):
    pass

def typed(a: int, *rest: str, **options: float) -> None:
    pass

class Thing:
    def __init__(self, x):
        self.x = x

    def method(self, y: int):
        return y

    @staticmethod
    def static(z) -> int:
        return 0

    @property
    def size(self):
        return 1

@dataclasses.dataclass
class Record:
    a: object
    b: Any
    c: int = 0
    d: tuple = ()
    e: tuple[int, ...] = ()
''', vars(module))
    objects = [("musclesim.planted", vars(module)[n]) for n in ("bare", "typed", "Thing",
                                                                 "Record")]
    found = problems(members(iter(objects)), classes(iter(objects)))
    assert found == {"musclesim.planted": [
        "musclesim.planted.bare: a, *rest, **options, return",
        "musclesim.planted.Thing.__init__: x",
        "musclesim.planted.Thing.method: return",
        "musclesim.planted.Thing.static: z",
        "musclesim.planted.Thing.size: return",
        "musclesim.planted.Record.a: field typed object, Any or a bare container",
        "musclesim.planted.Record.b: field typed object, Any or a bare container",
        "musclesim.planted.Record.d: field typed object, Any or a bare container"]}
    assert report(found).startswith("musclesim.planted: 8 without full annotations\n")
