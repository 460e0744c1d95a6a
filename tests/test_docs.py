"""Every public module, class and function is documented, and the docstring examples run."""
import doctest
import importlib
import inspect
import pkgutil

import pytest

import musclesim


def _modules():
    import musclesim.components as components

    for package in (musclesim, components):
        for info in pkgutil.walk_packages(package.__path__, package.__name__ + "."):
            yield importlib.import_module(info.name)


MODULES = list({m.__name__: m for m in _modules()}.values())


def _compiled(module):
    """(name, Python function) of each function of `module` compiled by musclesim.fmu.compiled.jit
    (a numba dispatcher keeps the function as ``py_func``; without numba it is the function)."""
    for name, obj in vars(module).items():
        fn = getattr(obj, "py_func", None)
        if fn is not None and getattr(fn, "__module__", None) == module.__name__:
            yield name, fn


@pytest.mark.parametrize("module", MODULES, ids=lambda m: m.__name__)
def test_public_objects_have_docstrings(module):
    assert inspect.getdoc(module), module.__name__
    for name, obj in vars(module).items():
        if name.startswith("_") or getattr(obj, "__module__", None) != module.__name__:
            continue
        if inspect.isfunction(obj) or inspect.isclass(obj):
            assert inspect.getdoc(obj), f"{module.__name__}.{name}"
    for name, fn in _compiled(module):
        if not name.startswith("_"):
            assert inspect.getdoc(fn), f"{module.__name__}.{name}"


@pytest.mark.parametrize("module", MODULES, ids=lambda m: m.__name__)
def test_docstring_examples(module):
    result = doctest.testmod(module)
    assert result.failed == 0
    runner = doctest.DocTestRunner()
    for name, fn in _compiled(module):  # doctest finds no compiled function: each by hand
        for test in doctest.DocTestFinder().find(fn, f"{module.__name__}.{name}", module=module,
                                                 globs=vars(module).copy()):
            runner.run(test)
    assert runner.failures == 0


def test_the_modelica_table_names_every_component_and_only_ports_it_has(fmu_dir):
    """docs/user/modelica.md: a row per component, and every port a row lists (with ``/`` and
    ``*`` shorthands expanded against the FMU) is one of the FMU's inputs or outputs."""
    import re
    from pathlib import Path

    from fmpy import read_model_description

    from musclesim.components import CATALOGUE

    text = (Path(__file__).parents[1] / "docs" / "user" / "modelica.md").read_text()
    rows = {m.group(1): m.group(2) for m in re.finditer(r"^\| `(\w+)`[^|]*\| ([^|]*→[^|]*)\|",
                                                           text, re.M)}
    for pair in re.finditer(r"^\| `(\w+)`, `(\w+)` \| ([^|]*→[^|]*)\|", text, re.M):
        rows.update({pair.group(1): pair.group(3), pair.group(2): pair.group(3)})
    assert set(CATALOGUE) <= set(rows)
    for name in CATALOGUE:
        md = read_model_description(str(fmu_dir / f"{name}.fmu"))
        ports = {v.name for v in md.modelVariables if v.causality in ("input", "output")}
        for port in re.findall(r"`([\w.\[\]/*]+)`", rows[name]):
            head, _, tails = port.rpartition(".")
            for one in ([f"{head}.{t}" for t in tails.split("/")] if "/" in port else [port]):
                if "*" in one or "[" in one:
                    prefix = one.split("*")[0].split("[")[0]
                    assert any(p.startswith(prefix) for p in ports), (name, one)
                else:
                    assert one in ports, (name, one)
