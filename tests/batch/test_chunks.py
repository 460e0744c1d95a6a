"""Cases in chunks (musclesim.batch.cases): a chunk of cases runs in one compiled pass, each case
with the bits and results.csv rows of its own run; a case that fails, or breaks the pass, keeps
its error to itself; chunks come about eight per worker within a bound on the values they hold."""
import numpy as np

from musclesim.batch import cases, chunks, run_case, run_chunk
from musclesim.cosim import csv_rows, load_scenario

from conftest import SCENARIOS

IDEAL = SCENARIOS / "crawler-ideal.toml"
POSITION = SCENARIOS / "sma-position-control.toml"


def _same(a, b):
    assert a.error == b.error
    assert (a.results is None) == (b.results is None)
    if a.results is not None:
        np.testing.assert_array_equal(a.results.data, b.results.data)
        np.testing.assert_array_equal(a.results.time, b.results.time)
        assert a.rows == b.rows == csv_rows(a.results.time, a.results.data).encode()
        assert a.units == b.units and a.hosts == b.hosts


def test_a_chunk_runs_in_one_pass_each_case_with_the_bits_and_rows_of_its_own_run(
        fmu_dir, passes):
    s = load_scenario(IDEAL, (), 0.5)
    chunk = [["inputs.f_f=0.5"], ["inputs.f_f=1.0"], []]
    together = run_chunk(s, fmu_dir, chunk)
    assert passes == [True]  # the three in one compiled call
    for a, b in zip(together, [run_case(s, fmu_dir, o) for o in chunk]):
        _same(a, b)
    assert together[0].results.data[-1, 0] != together[1].results.data[-1, 0]


def test_a_failing_case_or_one_that_breaks_the_pass_keeps_its_error_to_itself(
        fmu_dir, monkeypatch):
    s = load_scenario(IDEAL, (), 0.2)
    chunk = [["body.c=-1"], ["inputs.f_f=0.5"], ["nobody.c=1"]]
    out = run_chunk(s, fmu_dir, chunk)
    assert "c must be non-negative" in (out[0].error or out[0].results.error)
    assert out[1].results is not None and out[1].results.error is None
    assert out[2].results is None and "nobody" in out[2].error

    def broken(masters):
        raise RuntimeError("a bug in the pass")
    monkeypatch.setattr(cases, "run_together", broken)
    again = run_chunk(s, fmu_dir, chunk)  # each case alone, as if run on its own
    for a, b in zip(again, out):
        _same(a, b)


def test_chunks_come_about_eight_per_worker_within_the_values_bound():
    short = load_scenario(IDEAL, (), 10.0)  # 10 001 rows: a few hundred thousand values a case
    todo = [(f"c{k}", [f"inputs.f_f={k}"]) for k in range(100)]
    parts = chunks(todo, short, 3)
    assert [c for part in parts for c in part] == todo  # every case once, in order
    assert cases.PER_WORKER == 8
    assert len(parts) == 20 and len(parts[0]) == 5  # ceil(100 / 24) = 5 cases a chunk
    assert chunks(todo[:1], short, 3) == [todo[:1]]
    per_case = (short.n_steps + 1) * (len(short.recorded()) + 1)
    assert max(map(len, chunks(todo * 100, short, 1))) == cases.CHUNK_VALUES // per_case
    long = load_scenario(POSITION)  # 550 s at 2.5 kHz: one case is most of the bound
    assert {len(part) for part in chunks(todo, long, 2)} == {1}
