"""The package's public functions and methods, which tests/test_typing.py and
tests/test_docstrings.py hold to full annotations and documented parameters.

Public means: each framework layer's ``__all__`` (the layers: every subpackage of musclesim but
the components) (a name listed there that is a submodule stands
for that module's public names), and every module of ``musclesim.components`` (the components
import each other by module, so a module's public names are their interface: its ``__all__``,
or else the functions and classes it defines whose names do not start with ``_``). Of a public
class: its methods (public ones and ``__init__``) defined in it or in a base class of the
package, its properties, and, for a dataclass, its fields.
"""
from __future__ import annotations

import dataclasses
import functools
import importlib
import inspect
import pkgutil
from types import ModuleType
from typing import Any, Callable, Iterator, NamedTuple

import musclesim

LAYERS = tuple(info.name for info in pkgutil.iter_modules(musclesim.__path__)
               if info.ispkg and info.name != "components")


class Member(NamedTuple):
    """A public function or method: `layer` (the package whose interface holds it), `name`
    (module.qualname) and the function itself (`function`); `owner` is its class, or None; `bound`:
    its first parameter is self or cls."""

    layer: str
    name: str
    function: Callable[..., Any]
    owner: type | None
    bound: bool  # its first parameter is self or cls


def _defined_names(module: ModuleType) -> list[str]:
    """`module`'s ``__all__``, or the public functions and classes it defines itself."""
    if hasattr(module, "__all__"):
        return list(module.__all__)
    return [n for n, v in vars(module).items() if not n.startswith("_")
            and (inspect.isfunction(inspect.unwrap(v)) or inspect.isclass(v))
            and getattr(v, "__module__", None) == module.__name__]


def interface(package: ModuleType) -> Iterator[object]:
    """The objects `package`'s ``__all__`` (or its own public names) lists; a submodule listed
    stands for its own public names."""
    for name in _defined_names(package):
        value = getattr(package, name)
        if inspect.ismodule(value):
            yield from (getattr(value, n) for n in _defined_names(value))
        else:
            yield value


def _components() -> Iterator[ModuleType]:
    package = importlib.import_module("musclesim.components")
    yield package
    for info in pkgutil.walk_packages(package.__path__, "musclesim.components."):
        yield importlib.import_module(info.name)


def public_objects() -> Iterator[tuple[str, object]]:
    """(layer, object) of every public name, each object once (a layer may re-export
    another's)."""
    seen: set[int] = set()
    sources = [(f"musclesim.{layer}", importlib.import_module(f"musclesim.{layer}"), True)
               for layer in LAYERS]
    sources += [("musclesim.components", module, False) for module in _components()]
    for layer, module, is_interface in sources:
        objects = interface(module) if is_interface else (
            getattr(module, n) for n in _defined_names(module))
        for obj in objects:
            if callable(obj) and hasattr(obj, "__wrapped__"):  # functools.cache and the like
                obj = inspect.unwrap(obj)
            if id(obj) not in seen and (inspect.isfunction(obj) or inspect.isclass(obj)):
                seen.add(id(obj))
                yield layer, obj


def methods(cls: type) -> Iterator[tuple[Callable[..., Any], bool]]:
    """(function, whether its first parameter is self or cls) of the public methods, ``__init__``
    and property getters of `cls` that the package defines (in `cls` or a base of the package);
    a dataclass's generated ``__init__`` is left out (its fields are checked instead)."""
    done: set[str] = set()
    for base in cls.__mro__:
        if not base.__module__.startswith("musclesim"):
            continue
        for name, value in vars(base).items():
            if name in done or (name.startswith("_") and name != "__init__"):
                continue
            done.add(name)
            if name == "__init__" and dataclasses.is_dataclass(base) \
                    and base.__dataclass_params__.init:  # type: ignore[attr-defined]
                continue
            bound = not isinstance(value, staticmethod)
            if isinstance(value, (staticmethod, classmethod)):
                value = value.__func__
            elif isinstance(value, property):
                value = value.fget
            elif isinstance(value, functools.cached_property):
                value = value.func
            if inspect.isfunction(value):
                yield value, bound


def members(objects: Iterator[tuple[str, object]] | None = None) -> list[Member]:
    """Every public function and method of `objects` (default: `public_objects()`), each once."""
    out, seen = [], set()
    for layer, obj in objects if objects is not None else public_objects():
        if inspect.isfunction(obj):
            found = [(obj, None, False)]
        else:
            assert isinstance(obj, type)
            found = [(f, obj, bound) for f, bound in methods(obj)]
        for function, owner, bound in found:
            if id(function) not in seen:
                seen.add(id(function))
                out.append(Member(layer, f"{function.__module__}.{function.__qualname__}",
                                  function, owner, bound))
    return out


def classes(objects: Iterator[tuple[str, object]] | None = None) -> list[tuple[str, type]]:
    """(layer, class) of every public class of `objects` (default: `public_objects()`)."""
    return [(layer, obj) for layer, obj in (objects if objects is not None else public_objects())
            if isinstance(obj, type)]
