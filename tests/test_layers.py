"""The package's layering, read from the source's imports (no module is imported to check them).

Layers, each importing only those below it: errors and fmu < components < cosim < batch and
export (peers: many runs; a scenario packaged for other tools) < analysis, hysteresis, diagnosis
(peers, never importing each other) < benchmark (the diagnosis's blind test lab) and prediction
(the scenarios' outcomes with intervals from the diagnosis's fits; peers) < cli. Across layers a
module imports a framework layer's public interface only (`from musclesim.cosim import Master`,
the name listed in the layer's ``__all__``); inside a layer it imports its siblings by module. No
module uses another's ``_private`` names, and no import cycle joins modules.
"""
import ast
import importlib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SOURCES = {"musclesim": ROOT / "src" / "musclesim", "musclesim.components": ROOT / "components"}
RANK = {"errors": 0, "fmu": 0, "components": 1, "cosim": 2, "batch": 3, "export": 3, "analysis": 4,
        "hysteresis": 4, "diagnosis": 4, "benchmark": 5, "prediction": 5, "cli": 6, "root": 0}
FRAMEWORK = ("fmu", "cosim", "batch", "export", "analysis", "hysteresis", "diagnosis",
             "benchmark", "prediction")


def _module_files():
    files = {}
    for prefix, folder in SOURCES.items():
        for path in folder.rglob("*.py"):
            parts = list(path.relative_to(folder).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts = parts[:-1]
            files[".".join([prefix, *parts])] = path
    return files


FILES = _module_files()
TREES = {name: ast.parse(path.read_text(), str(path)) for name, path in FILES.items()}


def layer(module):
    """The layer a module of the package belongs to."""
    parts = module.split(".")
    if len(parts) == 1:
        return "root"
    return parts[1]


def _package_of(module):
    return module if FILES[module].name == "__init__.py" else module.rpartition(".")[0]


def _absolute(module, node):
    if node.level == 0:
        return node.module
    base = _package_of(module).split(".")
    base = base[:len(base) - node.level + 1]
    return ".".join(base + ([node.module] if node.module else []))


def imports(module):
    """Every import of `module` as (target module, name imported from it or None, line)."""
    out = []
    for node in ast.walk(TREES[module]):
        if isinstance(node, ast.Import):
            out += [(a.name, None, node.lineno) for a in node.names if a.name in FILES]
        elif isinstance(node, ast.ImportFrom):
            source = _absolute(module, node)
            if source not in FILES:
                continue
            for a in node.names:
                sub = f"{source}.{a.name}"
                out.append((sub, None, node.lineno) if sub in FILES
                           else (source, a.name, node.lineno))
    return out


def public_names(package):
    """The names a package's ``__all__`` lists (parsed, not imported)."""
    for node in TREES[package].body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", None) == "__all__"
                                                for t in node.targets):
            return set(ast.literal_eval(node.value))
    return set()


def _problems_of(module):
    problems = []
    here = layer(module)
    for target, name, line in imports(module):
        there = layer(target)
        where = f"{FILES[module].relative_to(ROOT)}:{line}"
        if there == here:
            if target == _package_of(module) and FILES[module].name != "__init__.py" \
                    and here in FRAMEWORK:
                problems.append(f"{where}: imports its own layer's interface {target} "
                                "(import the sibling module)")
        elif RANK[there] >= RANK[here]:
            problems.append(f"{where}: layer {here} imports {target} of layer {there}, "
                            "which is not below it")
        elif there in FRAMEWORK:
            package = f"musclesim.{there}"
            if target != package:
                problems.append(f"{where}: imports {target}; another layer imports only "
                                f"{package}'s interface")
            elif name is not None and name not in public_names(package):
                problems.append(f"{where}: {name} is not in {package}.__all__")
        if name is not None and name.startswith("_") and not name.startswith("__"):
            problems.append(f"{where}: imports the private name {name} of {target}")
    return problems


def _private_attributes(module):
    """Uses of ``alias._name`` where `alias` is an imported module of the package."""
    aliases = {}
    for node in ast.walk(TREES[module]):
        if isinstance(node, ast.ImportFrom):
            source = _absolute(module, node)
            for a in node.names:
                if f"{source}.{a.name}" in FILES:
                    aliases[a.asname or a.name] = f"{source}.{a.name}"
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name in FILES and a.asname:
                    aliases[a.asname] = a.name
    out = []
    for node in ast.walk(TREES[module]):
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) \
                and node.value.id in aliases and node.attr.startswith("_") \
                and not node.attr.startswith("__"):
            out.append(f"{FILES[module].relative_to(ROOT)}:{node.lineno}: uses "
                       f"{aliases[node.value.id]}.{node.attr}")
    return out


def cycles():
    """Import cycles between modules of the package, each as a list of modules."""
    graph = {m: sorted({t for t, _, _ in imports(m)} - {m}) for m in FILES}
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(v):  # Tarjan's strongly connected components
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def test_every_layer_imports_only_the_interfaces_of_layers_below_it():
    problems = [p for m in sorted(FILES) for p in _problems_of(m)]
    assert not problems, "\n".join(problems)


def test_no_module_uses_another_modules_private_names():
    problems = [p for m in sorted(FILES) for p in _private_attributes(m)]
    assert not problems, "\n".join(problems)


def test_no_import_cycles():
    assert not cycles()


@pytest.mark.parametrize("name", FRAMEWORK)
def test_each_layer_says_what_it_is_for_and_exports_its_interface(name):
    package = importlib.import_module(f"musclesim.{name}")
    assert package.__doc__ and len(package.__doc__.split()) > 10
    assert package.__all__, f"musclesim.{name} has no __all__"
    missing = [n for n in package.__all__ if not hasattr(package, n)]
    assert not missing, f"musclesim.{name}.__all__ names what it lacks: {missing}"
    # a name equal to a submodule's would shadow it: `from musclesim.x import m` is then ambiguous
    shadowing = [n for n in package.__all__ if f"musclesim.{name}.{n}" in FILES]
    assert not shadowing, f"musclesim.{name}.__all__ shadows its modules: {shadowing}"


def test_the_checks_find_what_they_look_for():
    """The parser sees a violation of each kind in code written to break the rules."""
    bad = {
        "musclesim.cosim.badmod": "from musclesim.diagnosis import diagnose\n"
                                  "from musclesim.cosim.master import _order\n",
        "musclesim.diagnosis.badmod": "from musclesim.cosim.master import Master\n"
                                      "from musclesim.cosim import NotExported\n"
                                      "from musclesim.cosim import scenario\nscenario._x\n",
        "musclesim.cosim.cyc_a": "from musclesim.cosim import cyc_b\n",
        "musclesim.cosim.cyc_b": "from musclesim.cosim import cyc_a\n",
    }
    for name, code in bad.items():
        FILES[name] = SOURCES["musclesim"] / (name.split(".", 1)[1].replace(".", "/") + ".py")
        TREES[name] = ast.parse(code)
    try:
        up = _problems_of("musclesim.cosim.badmod")
        assert any("not below it" in p for p in up) and any("private name _order" in p
                                                            for p in up)
        across = _problems_of("musclesim.diagnosis.badmod")
        assert any("imports musclesim.cosim.master" in p for p in across)
        assert any("NotExported is not in" in p for p in across)
        assert _private_attributes("musclesim.diagnosis.badmod")
        assert ["musclesim.cosim.cyc_a", "musclesim.cosim.cyc_b"] in cycles()
    finally:
        for name in bad:
            del FILES[name], TREES[name]
