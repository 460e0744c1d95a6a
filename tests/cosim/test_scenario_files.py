"""musclesim.cosim.scenario_files: a scenario's TOML files read along their ``extends`` chain,
merged, each in its own format (a format-1 file may not name a port format 2 renamed)."""
import numpy as np
import pytest

from musclesim.cosim import Master, Signal, renamed_signals, scenario
from musclesim.cosim.scenario_files import format_problem, read
from musclesim.errors import UserError

from conftest import SCENARIOS

S = Signal.parse


def test_an_extending_file_adds_lists_merges_tables_and_replaces_values(tmp_path):
    (tmp_path / "base.toml").write_text(
        'step = 0.1\nstop_time = 1.0\nrecord = ["a.y"]\n'
        '[instances.a]\ncomponent = "A"\nparameters = { k = 1.0, m = 2.0 }\n')
    (tmp_path / "variant.toml").write_text(
        'extends = "base.toml"\nstop_time = 2.0\nrecord = ["a.z"]\n'
        '[instances.a.parameters]\nk = 3.0\n')
    data = read(tmp_path / "variant.toml")
    assert data["stop_time"] == 2.0 and data["step"] == 0.1
    assert data["record"] == ["a.y", "a.z"]
    assert data["instances"]["a"] == {"component": "A", "parameters": {"k": 3.0, "m": 2.0}}


def test_a_file_that_extends_itself_is_refused(tmp_path):
    (tmp_path / "a.toml").write_text('extends = "b.toml"\n')
    (tmp_path / "b.toml").write_text('extends = "a.toml"\n')
    with pytest.raises(UserError, match="extends itself through"):
        read(tmp_path / "a.toml")


@pytest.mark.parametrize("value, ok", [(1, True), (2, True), (0, False), (3, False),
                                       (2.0, False), (True, False), ("2", False)])
def test_format_is_a_whole_number_from_1_to_2(value, ok):
    assert (format_problem(value) is None) == ok


def test_renamed_signals_are_typed_and_only_the_renamed_ones():
    components = {"pid": "PID", "wire": "SmaWire"}
    signals = [S("pid.y"), S("pid.r"), S("pid.e"), S("wire.T"), S("ghost.y")]
    assert renamed_signals(signals, components) == {S("pid.y"): S("pid.u_m"),
                                                    S("pid.r"): S("pid.u_s")}




PID_LOOP = """\
{format}step = 0.01
stop_time = 0.05
algorithm = "jacobi"
connections = [["ref.y", "pid.{r}"], ["ref.y", "pid.{y}"]]
record = ["pid.{out}"]
[instances.ref]
component = "SignalSource"
[instances.pid]
component = "PID"
"""


def test_a_file_without_format_2_may_not_name_a_port_format_2_renamed(tmp_path, fmu_dir):
    """The PID's ports took LimPID's names in format 2 and its y changed meaning (measurement ->
    output): a file that does not say format = 2 and names an old port is refused, with each new
    name, whatever the port's role; never read with the other meaning."""
    old = tmp_path / "old.toml"
    old.write_text(PID_LOOP.format(format="", r="r", y="y", out="u"))
    with pytest.raises(UserError) as err:
        scenario.load(old)
    assert str(err.value) == (
        f"scenario {old} names ports as before format 2 (the Modelica Standard Library's port "
        "names): 'pid.u' is pid.y now; 'pid.r' is pid.u_s now; 'pid.y' is pid.u_m now; write the "
        "new names and format = 2 at the top of the file")
    # the recorded y alone, the name that exists in both formats, is refused too
    alone = tmp_path / "alone.toml"
    alone.write_text(PID_LOOP.format(format="", r="u_s", y="u_m", out="y"))
    with pytest.raises(UserError, match=r"'pid.y' is pid.u_m now"):
        scenario.load(alone)
    # the same names with format = 2: y is the output, and the loop runs
    new = tmp_path / "new.toml"
    new.write_text(PID_LOOP.format(format="format = 2\n", r="u_s", y="u_m", out="y"))
    res = Master(scenario.load(new), fmu_dir).run()
    assert res.error is None and np.all(res[S("pid.y")] == 0.0)  # reference = measurement: e = 0
    # a format-1 file naming none of the renamed ports needs no format line
    assert scenario.load(SCENARIOS / "crawler-ideal-backward.toml").name
    for bad in ("3", "0", "2.0", "true"):
        new.write_text(PID_LOOP.format(format=f"format = {bad}\n", r="u_s", y="u_m", out="y"))
        with pytest.raises(UserError, match=r"format = .* is not one this musclesim reads "
                                            r"\(1 to 2\)"):
            scenario.load(new)


def test_each_file_of_an_extends_chain_is_read_in_its_own_format(tmp_path):
    """A variant without format 2 may extend a format-2 file (the base's pid.y is its output), so
    long as the variant itself names no renamed port."""
    (tmp_path / "base.toml").write_text(PID_LOOP.format(format="format = 2\n", r="u_s", y="u_m",
                                                        out="y"))
    variant = tmp_path / "variant.toml"
    variant.write_text('extends = "base.toml"\nstop_time = 0.02\nrecord = ["pid.e"]\n')
    assert scenario.load(variant).record == (S("pid.y"), S("pid.e"))
    variant.write_text('extends = "base.toml"\nrecord = ["pid.u"]\n')
    with pytest.raises(UserError, match=rf"scenario {variant} names ports as before format 2 .*"
                                        r"'pid.u' is pid.y now"):
        scenario.load(variant)

