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


@pytest.mark.parametrize("module", MODULES, ids=lambda m: m.__name__)
def test_public_objects_have_docstrings(module):
    assert inspect.getdoc(module), module.__name__
    for name, obj in vars(module).items():
        if name.startswith("_") or getattr(obj, "__module__", None) != module.__name__:
            continue
        if inspect.isfunction(obj) or inspect.isclass(obj):
            assert inspect.getdoc(obj), f"{module.__name__}.{name}"


@pytest.mark.parametrize("module", MODULES, ids=lambda m: m.__name__)
def test_docstring_examples(module):
    result = doctest.testmod(module)
    assert result.failed == 0
