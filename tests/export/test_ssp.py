"""SSP export: the archive is valid SSP 1.0, and libcosim, ecos and FMPy's SSP simulator run it.

Topology of scenarios/crawler-ideal.toml::

    inputs --f_a--> body --v, f_n, N--> friction1 --f--> body
           --u1---------------------->  friction1
           --u2---------------------->  friction2 (like friction1, block 2)
"""
import ctypes
import dataclasses
import math
import re
import sys
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import numpy as np
import pytest

from musclesim.cosim import Signal, scenario
from musclesim.export import ssp
from musclesim.components.crawler import body, friction, inputs
from musclesim.components.crawler.monolithic import simulate_ideal
from musclesim.errors import UserError
from musclesim.cosim.master import Master
from musclesim.fmu import step_end

from conftest import SCENARIOS

S = Signal.parse

IDEAL = SCENARIOS / "crawler-ideal.toml"
NS = ssp.NS
OVERRIDES = {"nominal": (), "overrides": ("body.k=150", "body.m2=0.25", "inputs.phi=2.2",
                                          "friction2.mu_k_high=0.6")}


def test_archive_is_valid_ssp_with_every_instance_connection_and_parameter(fmu_dir, tmp_path):
    s = scenario.load(IDEAL, OVERRIDES["overrides"], stop_time=2.0)
    path = ssp.export(s, fmu_dir, tmp_path / "sub" / "crawler.ssp")
    with zipfile.ZipFile(path) as zf:
        assert sorted(zf.namelist()) == ["SystemStructure.ssd", "resources/CrawlerBody.fmu",
                                         "resources/FrictionBlock.fmu",
                                         "resources/FrictionSwitchingInputs.fmu"]
        assert zf.read("resources/CrawlerBody.fmu") == (fmu_dir / "CrawlerBody.fmu").read_bytes()
        xml = zf.read("SystemStructure.ssd")
    root = ET.fromstring(xml)
    assert root.tag == f"{{{NS['ssd']}}}SystemStructureDescription"
    # the scenario crawler-ideal, named as an identifier (OMSimulator refuses "crawler-ideal")
    assert root.get("version") == "1.0" and root.get("name") == "crawler_ideal"
    assert root.find("ssd:System", NS).get("name") == "crawler_ideal"

    components = root.findall("ssd:System/ssd:Elements/ssd:Component", NS)
    assert {c.get("name"): c.get("source") for c in components} == {
        name: f"resources/{inst.component}.fmu" for name, inst in s.instances.items()}
    kinds = {(c.get("name"), k.get("name")): k.get("kind")
             for c in components for k in c.findall("ssd:Connectors/ssd:Connector", NS)}
    connections = root.findall("ssd:System/ssd:Connections/ssd:Connection", NS)
    assert [(Signal(c.get('startElement'), c.get('startConnector')),
             Signal(c.get('endElement'), c.get('endConnector'))) for c in connections] \
        == list(s.connections)
    for c in connections:
        assert kinds[c.get("startElement"), c.get("startConnector")] == "output"
        assert kinds[c.get("endElement"), c.get("endConnector")] == "input"
    units = {u.get("name") for u in root.findall("ssd:Units/ssc:Unit", NS)}
    body_f_a = root.find("ssd:System/ssd:Elements/ssd:Component[@name='body']/ssd:Connectors/"
                         "ssd:Connector[@name='f_a']/ssc:Real", NS)
    assert body_f_a.get("unit") == "N" and "N" in units

    for c in components:
        values = {p.get("name"): float(p.find("ssv:Real", NS).get("value"))
                  for p in c.iterfind(".//ssv:Parameter", NS)}
        assert values == s.instances[c.get("name")].parameters
        assert all(kinds[c.get("name"), name] == "parameter" for name in values)
    experiment = root.find("ssd:DefaultExperiment", NS)
    assert (float(experiment.get("startTime")), float(experiment.get("stopTime"))) == (0.0, 2.0)
    algorithm = experiment.find(".//osp:FixedStepAlgorithm", NS)
    assert float(algorithm.get("baseStepSize")) == s.step


def test_archive_passes_the_ssp_schemas(fmu_dir, tmp_path):
    """The schemas are the SSP 1.0 XSDs that FMPy ships; inline parameter sets are checked too.

    An instance that nothing connects, sets or records gets no (empty, invalid) Connectors.
    """
    from fmpy.ssp.ssd import read_ssd, validate_tree
    from lxml import etree

    s = scenario.load(IDEAL)
    spare = scenario.Instance("spare", "FrictionBlock")
    s = dataclasses.replace(s, instances={**s.instances, "spare": spare})
    path = ssp.export(s, fmu_dir, tmp_path / "crawler.ssp")
    with zipfile.ZipFile(path) as zf:
        root = etree.fromstring(zf.read("SystemStructure.ssd"))
    validate_tree(root, "SystemStructureDescription.xsd")
    sets = root.findall(".//ssv:ParameterSet", NS)
    assert len(sets) == 2  # inputs and body have parameter values, the friction blocks none
    for parameter_set in sets:
        validate_tree(parameter_set, "SystemStructureParameterValues.xsd")
    assert len(read_ssd(str(path)).system.elements) == 5


def test_integer_and_boolean_variables_are_typed_in_the_archive_and_libcosim_applies_them(
        fmu_dir, tmp_path):
    """Connectors and parameter values carry their FMI type (a relay's Boolean state, a data
    set's Integer number); the archive stays schema-valid, and libcosim sets a Boolean value: the
    wire driven by current instead of voltage heats differently."""
    from fmpy.ssp.ssd import validate_tree
    from lxml import etree

    def export(*sets):
        s = scenario.load(SCENARIOS / "sma-multiplier-bang-bang.toml",
                          ["wire.hysteresis=0", *sets], stop_time=0.5)
        path = ssp.export(s, fmu_dir, tmp_path / f"bb{len(sets)}.ssp")
        with zipfile.ZipFile(path) as zf:
            root = etree.fromstring(zf.read("SystemStructure.ssd"))
        validate_tree(root, "SystemStructureDescription.xsd")
        return s, path, root

    s, voltage, _ = export()
    _, current, root = export("wire.drive_current=1")
    kinds = {(c.getparent().getparent().get("name"), c.get("name")): c[0].tag.split("}")[1]
             for c in root.iter("{*}Connector")}
    assert kinds[("relay_m", "on")] == "Boolean" and kinds[("wire", "hysteresis")] == "Integer"
    assert kinds[("wire", "T")] == "Real"
    values = {(p.get("name"), p[0].tag.split("}")[1], p[0].get("value"))
              for p in root.iter("{*}Parameter")}
    assert {("drive_current", "Boolean", "true"), ("hysteresis", "Integer", "0")} <= values
    runs = [run_libcosim(path, ["wire.T"], s.n_steps, s.step)[1]["wire.T"]
            for path in (voltage, current)]
    assert not np.array_equal(*runs)


@pytest.mark.parametrize("name, change, message", [
    ("crawler.zip", None, "must have a name ending in .ssp"),
    ("crawler.ssp", {"connections": ((S("inputs.f_a"), S("body.f_b")),)},
     "has no variable 'f_b'"),
])
def test_export_refuses_what_a_user_can_fix(fmu_dir, tmp_path, name, change, message):
    s = scenario.load(IDEAL)
    if change:
        s = dataclasses.replace(s, **change)
    with pytest.raises(UserError, match=message):
        ssp.export(s, fmu_dir, tmp_path / name)
    assert not (tmp_path / name).exists()


def test_names_in_the_archive_are_identifiers(fmu_dir, tmp_path):
    """The system's, the components' and the parameter sets' names are identifiers in C's sense,
    as OMSimulator requires ("is not a valid ident"): the scenario crawler-ideal with an instance
    named friction-2 added is system crawler_ideal with a component friction_2; two instances
    that would share a name are refused."""
    assert [ssp.identifier(n) for n in ("crawler-ideal", "2wires", "ok_1", "sma wire")] == \
        ["crawler_ideal", "_2wires", "ok_1", "sma_wire"]
    s = scenario.load(IDEAL)
    extra = dataclasses.replace(s.instances["friction2"], name="friction-2")
    s = dataclasses.replace(s, instances={**s.instances, "friction-2": extra})
    with zipfile.ZipFile(ssp.export(s, fmu_dir, tmp_path / "crawler.ssp")) as zf:
        root = ET.fromstring(zf.read("SystemStructure.ssd"))
    named = [root, root.find("ssd:System", NS), *root.iter(f"{{{NS['ssd']}}}Component"),
             *root.iter(f"{{{NS['ssv']}}}ParameterSet")]
    names = {e.get("name") for e in named} | {c.get(end) for c in root.iter("{*}Connection")
                                               for end in ("startElement", "endElement")}
    assert "friction_2" in names and "crawler_ideal" in names
    assert [n for n in names if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", n)] == []
    twin = dataclasses.replace(extra, name="friction_2")
    s = dataclasses.replace(s, instances={**s.instances, "friction_2": twin})
    with pytest.raises(UserError, match="'friction-2' and 'friction_2' are both 'friction_2'"):
        ssp.export(s, fmu_dir, tmp_path / "twins.ssp")


def test_export_names_missing_fmus(tmp_path):
    with pytest.raises(UserError, match="has no FMU .*musclesim build"):
        ssp.export(scenario.load(IDEAL), tmp_path, tmp_path / "crawler.ssp")


# ---- running the archive in libcosim ------------------------------------------------------------
def run_libcosim(path, signals, n_steps, step):
    """Run the SSP archive at `path` with libcosim; return (time, {signal: values}) of rows 0..n."""
    from libcosimpy import CosimLogging
    from libcosimpy.CosimEnums import CosimErrorCode, CosimVariableType
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimObserver import CosimObserver

    CosimLogging.log_output_level(CosimLogging.CosimLogLevel.WARNING)
    execution = CosimExecution.from_ssp_file(str(path))  # step: the archive's OSP annotation
    observer = CosimObserver.create_time_series()
    execution.add_observer(observer)
    ids = {}
    for signal in map(str, signals):  # each tool's results keyed by the signal's string
        inst, var = Signal.parse(signal).instance, Signal.parse(signal).variable
        index = execution.slave_index_from_instance_name(inst)
        refs = {v.name.decode(): v.reference for v in execution.slave_variables(index)}
        ids[signal] = index, refs[var]
        observer.start_time_series(index, refs[var], CosimVariableType.REAL)
    ns = round(step * 1e9)  # libcosim's clock counts integer nanoseconds
    assert execution.simulate_until(n_steps * ns)
    assert CosimErrorCode(execution.status().error_code) == CosimErrorCode.SUCCESS
    values = {}
    for signal, (index, ref) in ids.items():
        # libcosimpy 0.0.6 trims a sample list by counting step numbers equal to 0 as unfilled,
        # so a read that includes step 0 loses its last sample: read step n separately
        samples = {}
        for first, count in ((0, n_steps + 1), (n_steps, 1)):
            times, steps, vals = observer.time_series_real_samples(index, ref, first, count)
            samples.update(zip(steps, zip(times, vals)))
        assert sorted(samples) == list(range(n_steps + 1))
        time = np.array([samples[k][0] for k in range(n_steps + 1)]) / 1e9
        values[signal] = np.array([samples[k][1] for k in range(n_steps + 1)])
    return time, values


# how each engine steps the system: Jacobi (every instance steps on the inputs transferred after
# the previous step) or ours (feedthrough resolved at each point); its clock; whether the inputs
# start from the instances' initial outputs or from 0; whether a row is stamped with the time the
# step that computed it started (FMPy's SSP simulator) or ended; whether a recorded output is read
# after the new inputs are set (`late`: a feedthrough output then shows them, as FMI 2 requires)
MASTERS = {
    "ours": dict(jacobi=False, clock="t0+kh", zero_start=False, stamp_start=False, late=False),
    "libcosim": dict(jacobi=True, clock="ns", zero_start=False, stamp_start=False, late=False),
    "ecos": dict(jacobi=True, clock="t+=h", zero_start=False, stamp_start=False, late=True),
    "fmpy-ssp": dict(jacobi=True, clock="t+=h", zero_start=True, stamp_start=True, late=False),
}


def crawler_reference(s, master):
    """Crawler-ideal (`s`, friction switching instantly) stepped as `master` steps it, in numpy.

    ours: at t_k the values are exchanged in feedthrough order, so the friction sees v(t_k),
    f_n(x_k, f_a(t_k)) and u(t_k); the points are t_k = t0 + k h.
    Jacobi (libcosim, ecos, FMPy's SSP simulator): every instance steps with the inputs
    transferred after the previous step and its outputs are read after its own step, so the
    feedthrough outputs at t_k are computed from inputs of t_k-1 (friction from v_k-1, f_n from
    f_a(t_k-1)). Their clocks: libcosim counts integer nanoseconds (t_k = k h in ns, each step
    t_k+1 - t_k); ecos and FMPy add the step (t += h). FMPy's SSP simulator starts every input
    at 0 (not the initial outputs) and stamps the values after a step with the time it started,
    one row per step while t < the stop time. ecos reads the values it records after it has
    set the new inputs: the friction force it shows at t_k is the one of v_k, f_n(x_k,
    f_a(t_k-1)) and u(t_k), not the one it passed to the body.
    Either way the inputs' source reads the time its step ends at as every slave does
    (`musclesim.fmu.step_end`).
    Returns (time, {signal: values}) for the signals crawler-ideal records.
    """
    m = MASTERS[master]
    bp, ip = (cls(**s.instances[n].parameters) for cls, n in
              ((body.BodyParams, "body"), (inputs.InputParams, "inputs")))
    fps = [friction.FrictionParams(**s.instances[n].parameters) for n in ("friction1", "friction2")]
    assert all(fp.t_switch == 0 for fp in fps)
    normal = body.normal_forces(bp)

    def friction_forces(v, f_n, u):
        return [friction.friction_force(v[i], f_n[i], normal[i], *friction.coefficients(u[i], fp),
                                        fp.v_s) for i, fp in enumerate(fps)]

    def clock(k, t):  # the point after k + 1 steps, from the point t after k
        return {"t0+kh": s.start_time + (k + 1) * s.step, "ns": (k + 1) * ns / 1e9,
                "t+=h": t + s.step}[m["clock"]]

    ns = round(s.step * 1e9)
    t, x = s.start_time, np.zeros(4)
    f_a, *u = inputs.signals(t, ip)
    f_n = body.nonfriction_forces(x, f_a, bp)
    forces = friction_forces(x[1::2], f_n, u)
    if m["zero_start"]:  # every input 0 in the first step
        f_a, u, f_n, forces = 0.0, [0.0, 0.0], [0.0, 0.0], [0.0, 0.0]
    rows, zoh, k, t_start = [], {}, 0, t
    while True:
        shown = friction_forces(x[1::2], f_n, u) if m["late"] else forces
        row = (x[0], x[1], x[2], x[3], body.centre_of_mass(x, bp), f_a, *u, *shown)
        if not m["stamp_start"]:
            rows.append((t, *row))
        elif k:
            rows.append((t_start, *row))
        if (k == s.n_steps) if not m["stamp_start"] else not t < s.stop_time:
            break
        h = clock(k, t) - t if m["clock"] == "ns" else s.step
        # like CrawlerBody: hold matrices are kept for steps within 1e-9 relative of the last
        if not zoh or not math.isclose(h, zoh["h"], rel_tol=1e-9):
            zoh = {"h": h, "AB": body.discretise(bp, h)}
        held = f_a, x[1::2], f_n, u  # the inputs each instance steps with
        x = body.step_state(x, (f_a, *forces), *zoh["AB"])
        t_end = step_end(s.start_time, t, h)  # the source's own time after its step
        t_start, t, k = t, clock(k, t), k + 1
        f_a, *u = inputs.signals(t_end, ip)
        f_n = body.nonfriction_forces(x, held[0] if m["jacobi"] else f_a, bp)
        forces = friction_forces(*held[1:]) if m["jacobi"] else friction_forces(x[1::2], f_n, u)
    names = ["body.flange_a.s", "body.flange_a.v", "body.flange_b.s", "body.flange_b.v",
             "body.x_cm", "inputs.f_a", "inputs.u1", "inputs.u2",
             "friction1.flange.f", "friction2.flange.f"]
    columns = np.array(rows).T
    return columns[0], dict(zip(names, columns[1:]))


def assert_close(time, values, ref_time, ref_values, rtol=1e-9):
    """Times within 1e-12 s, every signal within `rtol` of its largest magnitude."""
    np.testing.assert_allclose(time, ref_time, rtol=0, atol=1e-12)
    for signal, ref in ref_values.items():
        scale = max(np.abs(ref).max(), 1e-300)
        np.testing.assert_allclose(values[signal], ref, rtol=0, atol=rtol * scale, err_msg=signal)


@pytest.mark.parametrize("overrides", OVERRIDES.values(), ids=OVERRIDES.keys())
def test_libcosim_runs_the_archive_as_a_jacobi_master_that_delays_feedthrough(
        fmu_dir, tmp_path, overrides):
    """libcosim's result is the crawler stepped with libcosim's documented master, to 1e-9.

    libcosim's fixed-step algorithm steps all instances, reads their outputs after the step and
    transfers them to the connected inputs for the next step; it does not resolve direct
    feedthrough. A feedthrough output observed at t_k (friction force, the body's f_n) was thus
    computed from inputs of t_k-1: the friction acts one step late. Its observer stamps the values
    read after step k with t_k (from its integer-nanosecond clock), as ours does, so rows line up.

    Our master resolves feedthrough at each communication point (friction from the body's state
    at t_k), the zero-order-hold model the study uses (§ideal-actuation). The two results therefore
    differ once a block sticks or slips (nominal case: from 73 ms on, by 5-8 % of the block
    positions after 2 s and 1 % of x_cm after 60 s). `crawler_reference` reproduces each master
    with that difference as its only switch; both runners match it to 1e-9.
    """
    s = scenario.load(IDEAL, overrides, stop_time=2.0)
    path = ssp.export(s, fmu_dir, tmp_path / "crawler.ssp")
    time, values = run_libcosim(path, s.record, s.n_steps, s.step)
    np.testing.assert_array_equal(time, np.arange(s.n_steps + 1) * round(s.step * 1e9) / 1e9)
    assert_close(time, values, *crawler_reference(s, "libcosim"))

    ours = Master(s, fmu_dir).run()
    assert ours.error is None
    assert_close(ours.time, {str(c): ours[c] for c in ours.names}, *crawler_reference(s, "ours"))
    # the reference without libcosim's delays is the project's monolithic model
    ref_time, ref = crawler_reference(s, "ours")
    mono_time, states = simulate_ideal(
        body.BodyParams(**s.instances["body"].parameters),
        [friction.FrictionParams(**s.instances[n].parameters) for n in ("friction1", "friction2")],
        inputs.InputParams(**s.instances["inputs"].parameters), s.step, s.stop_time)
    flanges = ["body.flange_a.s", "body.flange_a.v", "body.flange_b.s", "body.flange_b.v"]
    assert_close(mono_time, dict(zip(flanges, states.T)), ref_time, {k: ref[k] for k in flanges})
    # and the delay matters: libcosim and our master part once the friction sticks or slips
    assert not np.allclose(values["body.flange_a.s"], ours[S("body.flange_a.s")], rtol=0, atol=1e-6)


# ---- running the archive in ecos and in FMPy's SSP simulator -------------------------------------
def run_ecos(path, signals, n_steps, step, parameter_set=None):
    """Run the SSP archive at `path` with ecos (ecospy); return (time, {signal: values}) of rows
    0..n, each read after the step (ecos's own clock)."""
    # ecospy's libecosc.so needs libtbb.so.12, which the pip package tbb (a test requirement) puts
    # in sys.prefix/lib, outside the loader's path: load it first
    ctypes.CDLL(str(Path(sys.prefix) / "lib" / "libtbb.so.12"), mode=ctypes.RTLD_GLOBAL)
    from ecospy import EcosSimulation

    ids = [f"{s.instance}::{s.variable}" for s in map(Signal.parse, map(str, signals))]
    times, rows = [], []
    with EcosSimulation(ssp_path=str(path), step_size=step) as sim:
        sim.init(parameter_set=parameter_set)
        for k in range(n_steps + 1):
            if k:
                sim.step()
            times.append(sim.get_time())
            rows.append([sim.get_real(i) for i in ids])
        sim.terminate()
    return np.array(times), dict(zip(map(str, signals), np.array(rows).T))


def run_fmpy_ssp(path, stop_time, step):
    """Run the SSP archive at `path` with FMPy's SSP simulator, with the parameters the archive
    binds to each component (FMPy applies only the set it is given); return (time, {signal:
    values})."""
    from fmpy.ssp.simulation import simulate_ssp
    from fmpy.ssp.ssd import Parameter, ParameterSet, find_components, read_ssd

    bound = ParameterSet(name="bound")
    for component in find_components(read_ssd(str(path)).system):
        for binding in component.parameterBindings:
            for pset in binding.parameterValues:
                bound.parameters += [Parameter(name=f"{component.name}.{p.name}", type=p.type,
                                               value=p.value) for p in pset.parameters]
    rows = simulate_ssp(str(path), stop_time=stop_time, step_size=step, parameter_set=bound)
    return rows["time"], {name: rows[name] for name in rows.dtype.names[1:]}


@pytest.mark.parametrize("overrides", OVERRIDES.values(), ids=OVERRIDES.keys())
def test_ecos_and_fmpys_ssp_simulator_run_the_archive_each_as_its_master_steps(
        fmu_dir, tmp_path, overrides):
    """ecos and FMPy's SSP simulator both run the archive as Jacobi masters, like libcosim, each
    with its own clock and reading (`MASTERS`); `crawler_reference` reproduces each bit for bit.

    ecos adds the step to its clock (t += h) and reads what it records after it has set the new
    inputs, so a feedthrough output it shows (the friction force) is not the one it passed on.
    FMPy's simulator also adds the step, starts every input at 0 rather than at the instances'
    initial outputs, and stamps the values after a step with the time the step started.
    """
    s = scenario.load(IDEAL, overrides, stop_time=2.0)
    path = ssp.export(s, fmu_dir, tmp_path / "crawler.ssp")
    for master, (time, values) in (("ecos", run_ecos(path, s.record, s.n_steps, s.step,
                                                          ssp.identifier(s.name))),
                                   ("fmpy-ssp", run_fmpy_ssp(path, s.stop_time, s.step))):
        ref_time, ref = crawler_reference(s, master)
        np.testing.assert_array_equal(time, ref_time, err_msg=master)
        for signal in map(str, s.record):
            np.testing.assert_array_equal(values[signal], ref[signal], err_msg=f"{master} {signal}")
    # each switch matters: ecos's late reading shows other friction forces than libcosim's
    # observer, and FMPy's zero start moves the blocks
    refs = {m: crawler_reference(s, m)[1] for m in ("libcosim", "ecos", "fmpy-ssp")}
    assert not np.array_equal(refs["ecos"]["friction1.flange.f"],
                              refs["libcosim"]["friction1.flange.f"])
    n = s.n_steps  # FMPy's row k holds what ecos's row k + 1 does
    assert not np.allclose(refs["fmpy-ssp"]["body.flange_a.s"][:n],
                           refs["ecos"]["body.flange_a.s"][1:], rtol=0, atol=1e-6)
