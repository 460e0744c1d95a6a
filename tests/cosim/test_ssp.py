"""SSP export: the archive is valid SSP 1.0, and libcosim (Open Simulation Platform) runs it.

Topology of scenarios/crawler-ideal.toml::

    inputs --f_a--> body --v, f_n, N--> friction1 --f--> body
           --u1---------------------->  friction1
           --u2---------------------->  friction2 (like friction1, block 2)
"""
import dataclasses
import math
import xml.etree.ElementTree as ET
import zipfile

import numpy as np
import pytest

from musclesim.cosim import scenario, ssp
from musclesim.components.crawler import body, friction, inputs
from musclesim.components.crawler.monolithic import simulate_ideal
from musclesim.errors import UserError
from musclesim.cosim.master import Master
from musclesim.fmu import step_end

from conftest import SCENARIOS

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
    assert root.get("version") == "1.0" and root.get("name") == "crawler-ideal"

    components = root.findall("ssd:System/ssd:Elements/ssd:Component", NS)
    assert {c.get("name"): c.get("source") for c in components} == {
        name: f"resources/{inst.component}.fmu" for name, inst in s.instances.items()}
    kinds = {(c.get("name"), k.get("name")): k.get("kind")
             for c in components for k in c.findall("ssd:Connectors/ssd:Connector", NS)}
    connections = root.findall("ssd:System/ssd:Connections/ssd:Connection", NS)
    assert [(f"{c.get('startElement')}.{c.get('startConnector')}",
             f"{c.get('endElement')}.{c.get('endConnector')}") for c in connections] \
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


@pytest.mark.parametrize("name, change, message", [
    ("crawler.zip", None, "must have a name ending in .ssp"),
    ("crawler.ssp", {"connections": (("inputs.f_a", "body.f_b"),)}, "has no variable 'f_b'"),
])
def test_export_refuses_what_a_user_can_fix(fmu_dir, tmp_path, name, change, message):
    s = scenario.load(IDEAL)
    if change:
        s = dataclasses.replace(s, **change)
    with pytest.raises(UserError, match=message):
        ssp.export(s, fmu_dir, tmp_path / name)
    assert not (tmp_path / name).exists()


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
    for signal in signals:
        inst, var = scenario.split_signal(signal)
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


def crawler_reference(s, libcosim):
    """Crawler-ideal (`s`, friction switching instantly) stepped as a master steps it, in numpy.

    libcosim=False, our master: at t_k the values are exchanged in feedthrough order, so the
    friction sees v(t_k), f_n(x_k, f_a(t_k)) and u(t_k); the points are t_k = k h.
    libcosim=True, libcosim's fixed-step master: every instance steps with the inputs transferred
    after the previous step and its outputs are read after its own step, so the feedthrough
    outputs at t_k are computed from inputs of t_k-1 (friction from v_k-1, f_n from f_a(t_k-1));
    time is t_k = k h counted in integer nanoseconds and each step is h = t_k+1 - t_k.
    Either way the inputs' source reads the time its step ends at as every slave does
    (`musclesim.fmu.step_end`).
    Returns (time, {signal: values}) for the signals crawler-ideal records.
    """
    bp, ip = (cls(**s.instances[n].parameters) for cls, n in
              ((body.BodyParams, "body"), (inputs.InputParams, "inputs")))
    fps = [friction.FrictionParams(**s.instances[n].parameters) for n in ("friction1", "friction2")]
    assert all(fp.t_switch == 0 for fp in fps)
    normal = body.normal_forces(bp)

    def friction_forces(v, f_n, u):
        return [friction.friction_force(v[i], f_n[i], normal[i], *friction.coefficients(u[i], fp),
                                        fp.v_s) for i, fp in enumerate(fps)]

    ns = round(s.step * 1e9)
    t, x = s.start_time, np.zeros(4)
    f_a, *u = inputs.signals(t, ip)
    f_n = body.nonfriction_forces(x, f_a, bp)
    forces = friction_forces(x[1::2], f_n, u)
    rows, zoh = [], {}
    for k in range(s.n_steps + 1):
        rows.append((t, x[0], x[1], x[2], x[3], body.centre_of_mass(x, bp), f_a, *u, *forces))
        if k == s.n_steps:
            break
        h = (k + 1) * ns / 1e9 - k * ns / 1e9 if libcosim else s.step
        # like CrawlerBody: hold matrices are kept for steps within 1e-9 relative of the last
        if not zoh or not math.isclose(h, zoh["h"], rel_tol=1e-9):
            zoh = {"h": h, "AB": body.discretise(bp, h)}
        held = f_a, x[1::2], f_n, u  # the inputs each instance steps with
        x = body.step_state(x, (f_a, *forces), *zoh["AB"])
        t_end = step_end(s.start_time, t, h)  # the source's own time after its step
        t = (k + 1) * ns / 1e9 if libcosim else s.start_time + (k + 1) * s.step
        f_a, *u = inputs.signals(t_end, ip)
        f_n = body.nonfriction_forces(x, held[0] if libcosim else f_a, bp)
        forces = friction_forces(*held[1:]) if libcosim else friction_forces(x[1::2], f_n, u)
    names = ["body.flange1.s", "body.flange1.v", "body.flange2.s", "body.flange2.v", "body.x_cm",
             "inputs.f_a", "inputs.u1", "inputs.u2", "friction1.flange.f", "friction2.flange.f"]
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
    positions after 2 s and 1 % of x_cm after 60 s), and for a second reason: our time
    accumulates t += h, so u1's edges, which fall on samples (t = 0.5 s, 1 s, ...), can switch
    one sample apart. `crawler_reference` reproduces each master with these two differences as
    its only switch; both runners match it to 1e-9.
    """
    s = scenario.load(IDEAL, overrides, stop_time=2.0)
    path = ssp.export(s, fmu_dir, tmp_path / "crawler.ssp")
    time, values = run_libcosim(path, s.record, s.n_steps, s.step)
    np.testing.assert_array_equal(time, np.arange(s.n_steps + 1) * round(s.step * 1e9) / 1e9)
    assert_close(time, values, *crawler_reference(s, libcosim=True))

    ours = Master(s, fmu_dir).run()
    assert ours.error is None
    assert_close(ours.time, {c: ours[c] for c in ours.names}, *crawler_reference(s, libcosim=False))
    # the reference without libcosim's delays is the project's monolithic model
    ref_time, ref = crawler_reference(s, libcosim=False)
    mono_time, states = simulate_ideal(
        body.BodyParams(**s.instances["body"].parameters),
        [friction.FrictionParams(**s.instances[n].parameters) for n in ("friction1", "friction2")],
        inputs.InputParams(**s.instances["inputs"].parameters), s.step, s.stop_time)
    flanges = ["body.flange1.s", "body.flange1.v", "body.flange2.s", "body.flange2.v"]
    assert_close(mono_time, dict(zip(flanges, states.T)), ref_time, {k: ref[k] for k in flanges})
    # and the delay matters: libcosim and our master part once the friction sticks or slips
    assert not np.allclose(values["body.flange1.s"], ours["body.flange1.s"], rtol=0, atol=1e-6)
