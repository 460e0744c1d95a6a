"""Export a scenario as one co-simulation FMU: FMPy's container FMU holding the scenario's FMUs.

Tools that take one FMU (Simulink, Dymola, PyFMI) run a whole scenario this way. The container's
runtime is FMPy's (its ``container_fmu`` binaries, read at export): at each of its fixed steps it
steps every instance with the inputs it holds, then passes the connections' values in the order
listed, each output read when its connection's turn comes, on the communication points our
master steps on (its results' time column is ours, bit for bit). Listing the connections in the
order of the sources' exchange (direct feedthrough first, `Master.exchange_order`) makes that
order the exchange of our Jacobi master, so a Jacobi scenario gives our results
(tests/export/test_container.py). With ``fmi=3`` the container is an FMI 3.0 FMU; the FMUs inside
may be of either version. A Gauss-Seidel scenario
runs as Jacobi there: it is refused rather than exported to other numbers. Multi-rate stepping
(``every``) the container cannot express: refused too.

The container FMU's variables: the scenario's values as parameters (``instance.parameter``, start
= the value), every input no connection feeds as an input (``instance.input``, start = the value
the scenario sets, else the FMU's start value: a replayed signal sets it), and the recorded
signals as outputs, with their units. Its default experiment is the scenario's start, stop and
step.

FMPy 0.3.32's own packager writes connections of FMI 2.0 FMUs with a type its runtime refuses and
leaves a stray archive inside the FMU; the packaging here is ours (a model description, the
runtime's ``container.json``, the FMUs unpacked under ``resources/``).
"""
from __future__ import annotations

import json
import tempfile
import uuid
import zipfile
from pathlib import Path
from typing import Any
from xml.etree import ElementTree as ET

from musclesim.cosim import (KINDS, Master, ParamRef, Scenario, Signal, check_archive,
                             compile_loader, replace_zip)
from musclesim.errors import UserError
from musclesim.export.ssp import base_units, identifier, value_text

# (name, causality, instance, its model variable, start value as text or None)
Variable = tuple[str, str, str, Any, "str | None"]
CONTAINER_VERSION = "0.1.0"  # the container.json format of FMPy's container runtime
RUNTIME_SUFFIX = ".runtime.so"  # FMPy's runtime behind the grid loader: container_fmu + this
_PLATFORMS = (("x86_64-linux", "linux64", "container_fmu.so"),
              ("x86_64-windows", "win64", "container_fmu.dll"),
              ("x86_64-darwin", "darwin64", "container_fmu.dylib"))


def _runtime() -> Path:
    """Folder of FMPy's container runtime binaries."""
    import fmpy.container_fmu
    return Path(fmpy.container_fmu.__file__).parent / "binaries"


# per kind: the FMI 2.0 type element, the FMI 3.0 variable element, the container runtime's type
_TYPES = {"Real": ("Real", "Float64"), "Integer": ("Integer", "Int32"),
          "Boolean": ("Boolean", "Boolean")}


def _variables(scenario: Scenario, master: Master) -> list[Variable]:
    """[(name, causality, instance, its variable, start value as text or None)] of the
    container, in value-reference order (from 1): a parameter or input starts at the value the
    scenario sets, else at the FMU's start value; an output has none."""
    targets = {dst for _, dst in scenario.connections}
    out, named = [], set()

    def add(name: str, causality: str, inst: str, var: Any) -> None:
        if name not in named:
            named.add(name)
            value = None if causality == "output" else \
                scenario.instances[inst].parameters.get(var.name, var.start)
            out.append((name, causality, inst, var,
                        None if value is None else value_text(KINDS[var.type], value)))

    for name, spec in scenario.instances.items():
        for par in spec.parameters:
            v = master.instances[name].vars[par]
            if v.causality == "parameter":
                add(str(ParamRef(name, par)), "parameter", name, v)
    for name, inst in master.instances.items():
        for v in inst.md.modelVariables:
            if v.causality == "input" and Signal(name, v.name) not in targets:
                add(str(Signal(name, v.name)), "input", name, v)
    for signal in master.columns:  # the recorded signals
        add(str(signal), "output", signal.instance,
            master.instances[signal.instance].vars[signal.variable])
    return out


def model_description(scenario: Scenario, master: Master, variables: list[Variable],
                      fmi: int = 2) -> ET.Element:
    """The container's ``fmiModelDescription`` element (FMI `fmi`.0 co-simulation) of `scenario`
    checked by `master`, declaring the container's `variables` (`_variables`)."""
    token = {2: "guid", 3: "instantiationToken"}[fmi]
    root = ET.Element("fmiModelDescription", {
        # OMSimulator and the like take a model name that is an identifier
        "fmiVersion": f"{fmi}.0", "modelName": identifier(scenario.name),
        token: "{" + str(uuid.uuid4()) + "}",
        "generationTool": "musclesim",
        "description": scenario.description or f"scenario {scenario.name}",
        "variableNamingConvention": "flat",
        **({"numberOfEventIndicators": "0"} if fmi == 2 else {})})
    ET.SubElement(root, "CoSimulation", modelIdentifier="container_fmu",
                  canHandleVariableCommunicationStepSize="true")
    units = base_units(master)
    shown = {u.name: u.displayUnits for i in master.instances.values()
             for u in i.md.unitDefinitions}
    used = sorted({v.unit for _, _, _, v, _ in variables if v.unit in units})
    if used:
        defs = ET.SubElement(root, "UnitDefinitions")
        for name in used:
            unit = ET.SubElement(defs, "Unit", name=name)
            ET.SubElement(unit, "BaseUnit", units[name])
            for d in shown[name]:
                ET.SubElement(unit, "DisplayUnit", name=d.name, factor=repr(float(d.factor)),
                              offset=repr(float(d.offset)))
    ET.SubElement(root, "DefaultExperiment", startTime=repr(scenario.start_time),
                  stopTime=repr(scenario.stop_time), stepSize=repr(scenario.step))
    mv = ET.SubElement(root, "ModelVariables")

    def variable(attrs: dict[str, str], real: dict[str, Any], kind: str = "Real") -> None:
        """An FMI 2.0 ScalarVariable with its type element (Real, ...), or an FMI 3.0 variable
        (Float64, ...) holding both."""
        real = {k: x for k, x in real.items() if x is not None}
        if fmi == 3:
            ET.SubElement(mv, _TYPES[kind][1], {**attrs, **real})
        else:
            ET.SubElement(ET.SubElement(mv, "ScalarVariable", attrs), _TYPES[kind][0], real)

    variable({"name": "time", "valueReference": "0", "causality": "independent",
              "variability": "continuous", "description": "Simulation time"}, {})
    for vr, (name, causality, _, v, start) in enumerate(variables, start=1):
        attrs = {"name": name, "valueReference": str(vr), "causality": causality,
                 "description": v.description or name}
        real, kind = {"start": start}, KINDS[v.type]
        changing = "continuous" if kind == "Real" else "discrete"
        if causality == "parameter":
            attrs.update(variability="fixed", initial="exact")
        elif causality == "input":
            attrs["variability"] = changing
        else:
            attrs.update(variability=changing, initial="calculated")
        if v.unit in units and kind == "Real":
            real["unit"] = v.unit
            if v.displayUnit:
                real["displayUnit"] = v.displayUnit
        variable(attrs, real, kind)
    structure = ET.SubElement(root, "ModelStructure")
    outputs = [vr for vr, (_, c, *_) in enumerate(variables, start=1) if c == "output"]
    if fmi == 3:  # by value reference
        for kind in ("Output", "InitialUnknown"):
            for vr in outputs:
                ET.SubElement(structure, kind, valueReference=str(vr))
        return root
    # FMI 2.0: a variable's index is its position in ModelVariables, from 1 (time is the first)
    for section in ("Outputs", "InitialUnknowns"):
        node = ET.SubElement(structure, section)
        for vr in outputs:
            ET.SubElement(node, "Unknown", index=str(vr + 1))
    return root


def configuration(scenario: Scenario, master: Master, variables: list[Variable],
                  guid: str | None) -> dict[str, Any]:
    """The container runtime's ``container.json`` for `scenario` checked by `master`, mapping
    the container's `variables` onto the instances'; `guid` is the container's token."""
    names = list(master.instances)
    index = {n: i for i, n in enumerate(names)}
    position = {n: i for i, n in enumerate(master.exchange_order)}

    def ref(signal: Signal) -> tuple[int, int]:
        return index[signal.instance], \
            master.instances[signal.instance].vars[signal.variable].valueReference

    connections = []
    for link in sorted(scenario.graph.links, key=lambda k: position[k.source]):
        (a, va), (b, vb) = ref(link.src), ref(link.dst)
        kind = _TYPES[KINDS[master.instances[link.source].vars[link.output].type]][1]
        connections.append({"variableType": kind, "srcComponent": a, "dstComponent": b,
                             "srcValueReferences": [va], "dstValueReferences": [vb],
                             "size": 1})
    data: dict[str, Any] = {
        "containerVersion": CONTAINER_VERSION, "instantiationToken": guid,
        "fixedStepSize": scenario.step, "parallelDoStep": False,
        "components": [{"fmiMajorVersion": master.instances[n].md.fmiVersion[0], "name": n,
                        "instantiationToken": master.instances[n].md.guid,
                        "modelIdentifier": master.instances[n].md.coSimulation.modelIdentifier,
                        "path": master.instances[n].component} for n in names],
        "variables": [], "connections": connections,
    }
    for _, _, inst, v, start in variables:
        variable = {"variableType": _TYPES[KINDS[v.type]][1],
                    "mappings": [[index[inst], v.valueReference]]}
        if start is not None:
            variable["start"] = [start]
        data["variables"].append(variable)
    return data


def export(scenario: Scenario, fmu_dir: str | Path, fmu_path: str | Path, fmi: int = 2) -> Path:
    """Write `scenario` with its FMUs from `fmu_dir` (FMI 2.0 or 3.0, or both) as the one FMI
    `fmi`.0 co-simulation FMU `fmu_path` (see the module); return its path.

    Raises
    ------
    UserError
        If the path does not end in ``.fmu`` or names a folder, the scenario's wiring does not
        match its FMUs, it uses Gauss-Seidel or multi-rate stepping, or this platform has no
        container runtime in the installed FMPy.
    """
    if fmi not in (2, 3):
        raise UserError(f"FMI version {fmi!r}: a container FMU is FMI 2.0 or 3.0 (2 or 3)")
    fmu_path, fmu_dir = check_archive(fmu_path, ".fmu", "the FMU"), Path(fmu_dir)
    if scenario.algorithm != "jacobi":
        raise UserError(f"scenario {scenario.path}: the container FMU steps its FMUs as the "
                        "Jacobi algorithm does; a Gauss-Seidel scenario would give other "
                        "results there (set algorithm = \"jacobi\" to export it as such)")
    slow = [n for n, i in scenario.instances.items() if i.every > 1]
    if slow:
        raise UserError(f"scenario {scenario.path}: instance {slow[0]!r} steps every "
                        f"{scenario.instances[slow[0]].every} points; the container FMU steps "
                        "every instance at every point")
    runtime = _runtime()
    if not runtime.is_dir():
        raise UserError("the installed FMPy has no container runtime (fmpy/container_fmu/"
                        "binaries): FMPy 0.3.32 or later has it")
    master = Master(scenario, fmu_dir)
    variables = _variables(scenario, master)
    root = model_description(scenario, master, variables, fmi)
    ET.indent(root)
    config = configuration(scenario, master, variables,
                           root.get("guid") or root.get("instantiationToken"))

    def fill(archive: zipfile.ZipFile, tmp: Path) -> None:
        archive.writestr("modelDescription.xml",
                         ET.tostring(root, encoding="UTF-8", xml_declaration=True))
        archive.writestr("resources/container.json", json.dumps(config, indent=2))
        loader = _grid_loader(tmp, scenario.step) if fmi == 2 else None
        for platform, folder, library in _PLATFORMS:
            if (runtime / platform / library).is_file():  # FMI 3.0 names its folders so
                where = f"binaries/{folder if fmi == 2 else platform}/{library}"
                if loader is not None and folder == "linux64":  # the runtime behind the loader
                    archive.write(loader, where)
                    where = where.removesuffix(".so") + RUNTIME_SUFFIX
                archive.write(runtime / platform / library, where)
        for comp in sorted({i.component for i in scenario.instances.values()}):
            with zipfile.ZipFile(fmu_dir / f"{comp}.fmu") as inner:
                for item in inner.infolist():
                    if not item.is_dir():
                        archive.writestr(f"resources/{comp}/{item.filename}", inner.read(item))

    with tempfile.TemporaryDirectory(prefix="musclesim_export_") as tmp:
        return replace_zip(fmu_path, lambda archive: fill(archive, Path(tmp)))


def _grid_loader(folder: Path, step: float) -> Path | None:
    """The loader that puts a drifted host clock back on the container's grid of `step`
    (`musclesim.cosim.compile_loader`), compiled into `folder`, or None where it cannot be
    (not Linux, no compiler): FMPy's runtime alone then, which refuses such a step."""
    try:
        return compile_loader(folder, grid_step=step, suffix=RUNTIME_SUFFIX)
    except RuntimeError:
        return None
