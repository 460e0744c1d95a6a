"""SSP export: a scenario and its FMUs as an SSP 1.0 archive (SystemStructure.ssd + resources/)."""
from __future__ import annotations

import re
import zipfile
from pathlib import Path
from typing import Any
from xml.etree import ElementTree as ET

from musclesim.cosim import KINDS, Master, Scenario, check_archive, replace_zip
from musclesim.errors import UserError

NS = {
    "ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
    "ssc": "http://ssp-standard.org/SSP1/SystemStructureCommon",
    "ssv": "http://ssp-standard.org/SSP1/SystemStructureParameterValues",
    "osp": "http://opensimulationplatform.com/SSP/OSPAnnotations",
}
# FMI 2.0 causalities that are SSP connector kinds of the same name; others get no connector
_KINDS = ("input", "output", "parameter", "calculatedParameter")
_BASE_UNIT = ("kg", "m", "s", "A", "K", "mol", "cd", "rad")
_SCALING = (("factor", 1.0), ("offset", 0.0))

# libcosim matches element names with these prefixes literally, so the archive must use them
for _prefix, _uri in NS.items():
    ET.register_namespace(_prefix, _uri)


def _tag(qname: str) -> str:
    """``"ssd:System"`` -> ``"{http://...}System"``."""
    prefix, _, local = qname.partition(":")
    return f"{{{NS[prefix]}}}{local}"


def _sub(parent: Any, qname: str, **attrib: str) -> ET.Element:
    return ET.SubElement(parent, _tag(qname), attrib)


def _used_variables(scenario: Scenario) -> dict[str, set[str]]:
    """``{instance: set of variable names}`` that the scenario connects, sets or records."""
    signals = [s for pair in scenario.connections for s in pair] + scenario.recorded()
    used = {name: set(inst.parameters) for name, inst in scenario.instances.items()}
    for signal in signals:
        used[signal.instance].add(signal.variable)
    return used


def base_units(master: Master) -> dict[str, dict[str, str]]:
    """The unit definitions of `master`'s components as ``BaseUnit`` attributes (SSC's and FMI
    2.0's are the same), ``{name: {attr: text}}``; a unit two FMUs define differently is
    refused."""
    units: dict[str, dict[str, str]] = {}
    for inst in master.instances.values():
        for unit in inst.md.unitDefinitions:
            if unit.baseUnit is None:
                continue
            base = unit.baseUnit
            attrib = {k: str(getattr(base, k)) for k in _BASE_UNIT if getattr(base, k)}
            attrib.update({k: repr(float(getattr(base, k))) for k, default in _SCALING
                           if getattr(base, k) != default})
            if units.setdefault(unit.name, attrib) != attrib:
                raise UserError(f"unit {unit.name!r} of {inst.component} is defined differently "
                                "in another component's FMU")
    return units


def identifier(name: str) -> str:
    """`name` as an identifier in C's sense (ASCII letters, digits and underscores, not starting
    with a digit; ``crawler-ideal`` -> ``crawler_ideal``): what OMSimulator requires of a system's,
    a component's and a model's name ("is not a valid ident"), and so what the exports write
    there. Every other character becomes an underscore; a leading digit gets one before it.

    Parameters
    ----------
    name : str
        A scenario's or an instance's name.

    Returns
    -------
    str
    """
    ident = re.sub(r"[^A-Za-z0-9_]", "_", name)
    return ident if ident and not ident[0].isdigit() else f"_{ident}"


def _element_names(scenario: Scenario) -> dict[str, str]:
    """{instance: its component's name in the SSD} (`identifier`), refused where two instances
    would get the same one."""
    names = {name: identifier(name) for name in scenario.instances}
    seen: dict[str, str] = {}
    for name, ident in names.items():
        if ident in seen:
            raise UserError(f"scenario {scenario.path}: instances {seen[ident]!r} and {name!r} "
                            f"are both {ident!r} as identifiers (SSP tools such as OMSimulator "
                            "take letters, digits and underscores only); rename one")
        seen[ident] = name
    return names


def value_text(kind: str, value: float) -> str:
    """`value` of a variable of `kind` (Real, Integer, Boolean) as text, as SSP and FMI model
    descriptions write it."""
    value = float(value)
    return {"Real": repr(value), "Integer": str(int(value)),
            "Boolean": "true" if value else "false"}[kind]


def _parameter_binding(component: ET.Element, set_name: str, parameters: dict[str, float],
                       variables: dict[str, Any]) -> None:
    """Bind ``{name: value}`` to `component` as an inline ``ssv:ParameterSet``, each value typed
    as its variable (`variables`: {name: fmpy ScalarVariable})."""
    binding = _sub(_sub(component, "ssd:ParameterBindings"), "ssd:ParameterBinding")
    pset = _sub(_sub(binding, "ssd:ParameterValues"), "ssv:ParameterSet",
                version="1.0", name=set_name)
    params = _sub(pset, "ssv:Parameters")
    for name, value in parameters.items():
        kind = KINDS[variables[name].type]
        _sub(_sub(params, "ssv:Parameter", name=name), f"ssv:{kind}", value=value_text(kind, value))


def system_structure(scenario: Scenario, master: Master) -> ET.Element:
    """Build the ``ssd:SystemStructureDescription`` element of `scenario` (checked by `master`).

    Parameters
    ----------
    scenario : musclesim.cosim.Scenario
    master : musclesim.cosim.Master
        A master of the same scenario: its checked wiring and the FMUs' model descriptions.

    Returns
    -------
    xml.etree.ElementTree.Element
    """
    units = base_units(master)
    used = _used_variables(scenario)
    element, ident = _element_names(scenario), identifier(scenario.name)
    root = ET.Element(_tag("ssd:SystemStructureDescription"), version="1.0", name=ident)
    system = _sub(root, "ssd:System", name=ident)
    if scenario.description:
        system.set("description", scenario.description)
    elements = _sub(system, "ssd:Elements")
    referenced = set()
    for name, spec in scenario.instances.items():
        inst = master.instances[name]
        comp = _sub(elements, "ssd:Component", name=element[name],
                    type="application/x-fmu-sharedlibrary",
                    source=f"resources/{spec.component}.fmu")
        variables = [v for v in inst.md.modelVariables
                     if v.name in used[name] and v.causality in _KINDS]
        connectors = _sub(comp, "ssd:Connectors") if variables else None
        for var in variables:
            kind = KINDS[var.type]
            real = _sub(_sub(connectors, "ssd:Connector", name=var.name, kind=var.causality),
                        f"ssc:{kind}")
            if var.unit in units and kind == "Real":
                real.set("unit", var.unit)
                referenced.add(var.unit)
        if spec.parameters:
            _parameter_binding(comp, ident, spec.parameters, inst.vars)
        if spec.every > 1:  # libcosim steps it every `every`-th point (its decimation factor)
            note = _sub(_sub(comp, "ssd:Annotations"), "ssc:Annotation",
                        type="com.opensimulationplatform")
            _sub(note, "osp:StepSizeHint", value=repr(spec.every * scenario.step))
    connections = _sub(system, "ssd:Connections") if scenario.connections else None
    for link in scenario.graph.links:
        _sub(connections, "ssd:Connection", startElement=element[link.source],
             startConnector=link.output, endElement=element[link.target], endConnector=link.input)
    if referenced:
        defs = _sub(root, "ssd:Units")
        for unit in sorted(referenced):
            _sub(_sub(defs, "ssc:Unit", name=unit), "ssc:BaseUnit", **units[unit])
    experiment = _sub(root, "ssd:DefaultExperiment", startTime=repr(scenario.start_time),
                      stopTime=repr(scenario.stop_time))
    # SSP has no field for the communication step; libcosim reads it from this annotation
    annotation = _sub(_sub(experiment, "ssd:Annotations"), "ssc:Annotation",
                      type="com.opensimulationplatform")
    _sub(_sub(annotation, "osp:Algorithm"), "osp:FixedStepAlgorithm",
         baseStepSize=repr(scenario.step))
    return root


def export(scenario: Scenario, fmu_dir: str | Path, ssp_path: str | Path) -> Path:
    """Write `scenario` with its FMUs as the SSP 1.0 archive `ssp_path`.

    Parameters
    ----------
    scenario : musclesim.cosim.Scenario
    fmu_dir : str or Path
        Folder with ``<component>.fmu`` files (output of ``musclesim build``).
    ssp_path : str or Path
        The archive to write (replaced if it exists); its name must end in ``.ssp``.

    Returns
    -------
    Path
        `ssp_path`.

    Raises
    ------
    UserError
        If the path does not end in ``.ssp`` or names a folder, or if the scenario's wiring does
        not match its FMUs (as `musclesim.cosim.Master` checks it).

    Notes
    -----
    The archive describes the system, not how to step it: SSP 1.0 cannot state a master
    algorithm, so the communication step goes into the Open Simulation Platform annotation that
    libcosim reads, as does an instance's own step (``every`` steps: its ``StepSizeHint``), and
    each tool steps the system with its own master. libcosim's fixed-step
    master passes values only after all instances stepped, so it delays direct feedthrough by one
    step where ours resolves it at each communication point (tests/export/test_ssp.py shows both).

    Examples
    --------
    >>> from musclesim.cosim import load_scenario
    >>> from musclesim.export import export_ssp
    >>> s = load_scenario("scenarios/crawler-ideal.toml")
    >>> export_ssp(s, "fmus", "crawler.ssp")  # doctest: +SKIP
    PosixPath('crawler.ssp')
    """
    ssp_path, fmu_dir = check_archive(ssp_path, ".ssp", "the SSP archive"), Path(fmu_dir)
    root = system_structure(scenario, Master(scenario, fmu_dir))
    ET.indent(root)

    def fill(archive: zipfile.ZipFile) -> None:
        archive.writestr("SystemStructure.ssd",
                         ET.tostring(root, encoding="UTF-8", xml_declaration=True))
        for comp in sorted({i.component for i in scenario.instances.values()}):
            archive.write(fmu_dir / f"{comp}.fmu", f"resources/{comp}.fmu")
    return replace_zip(ssp_path, fill)
