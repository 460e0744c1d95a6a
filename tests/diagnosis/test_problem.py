"""The units a diagnosis simulates (`musclesim.diagnosis.problem`): instances that nothing fitted
can change are simulated once and replayed, giving every run what simulating them gives."""
from dataclasses import replace

import numpy as np

from musclesim.cosim import ParamRef, Signal, load_scenario, reuse_fmus
from musclesim.diagnosis import dataset
from musclesim.diagnosis.problem import Problem, _sources
from musclesim.diagnosis.simulate import simulate

from conftest import SCENARIOS

OBSERVED = (Signal("thermocouple", "T_meas"), Signal("wire", "strain"))


def test_sources_are_the_instances_nothing_fitted_reaches():
    """On the tracking bench: the constant load and the reference (signal sources, no effect, no
    calibration parameter), not the controller that reads the thermocouple; none that is
    observed, and none under Gauss-Seidel, where a reader stepped after a source takes its
    output after its step, not the one recorded at the communication point."""
    s = load_scenario(SCENARIOS / "sma-bench-tracking.toml")
    assert _sources(s, OBSERVED) == {"load", "reference"}
    assert _sources(s, OBSERVED + (Signal("load", "y"),)) == {"reference"}
    assert _sources(replace(s, algorithm="gauss-seidel"), OBSERVED) == set()


def test_a_source_replayed_gives_every_run_what_simulating_it_gives(fmu_dir):
    """Every unit of the independent tracking bench's data set: the load runs once for them all
    (not the reference and controller, which feed nothing there), its force is replayed into the
    wire, and the runs of a fit (training part, values changed) are the same to the bit as with
    the load simulated in each."""
    ds = dataset.load(SCENARIOS / "data" / "sma-independent-thermocouple-lag")
    problem = Problem(ds, fmu_dir)
    units = [problem.unit("model"), problem.replayed(), *problem.isolation_units()]
    assert len(problem._recorded) == 1  # the load alone, once for all the units
    values = {ParamRef("wire", "h"): 110.0, ParamRef("thermocouple", "tau"): 0.2}
    with reuse_fmus():
        for unit in units:
            run = unit.runs[0]
            assert run.sources == ("load",) and set(run.fed) == {Signal("wire", "flange.f")}
            assert "load" in unit.instances  # still a member: only its simulation is saved
            simulated = replace(unit, runs=[replace(r, sources=(), fed={}) for r in unit.runs])
            for a, b in zip(simulate(unit, values, fmu_dir, part=0),
                            simulate(simulated, values, fmu_dir, part=0)):
                for column in a:
                    assert np.array_equal(a[column], b[column], equal_nan=True), column
