"""musclesim.cosim.scenario: a scenario file parsed into typed addresses (each signal once), its
checks collecting every problem, ``--set`` parsed at the edge and applied by `with_values`."""
import math

import pytest

from musclesim.cosim import (Instance, Metric, Panel, ParamRef, Scenario, Signal, apply_overrides,
                             load_scenario, with_values)
from musclesim.errors import UserError

from conftest import SCENARIOS

S = Signal.parse

TEXT = """\
format = 2
name = "pair"
step = 0.5
stop_time = 2.0
connections = [["src.y", "body.f_a"]]
record = ["body.flange_a.s"]
[instances.src]
component = "SignalSource"
parameters = { amplitude = 2 }
[instances.body]
component = "CrawlerBody"
every = 2
[metrics.reach]
signal = "body.flange_a.s"
op = "max"
over = "src.y"
[[plots]]
title = "force"
signals = ["src.y", "body.f_a"]
"""


def write(tmp_path, text, name="s.toml"):
    (tmp_path / name).write_text(text)
    return tmp_path / name


def test_a_file_parses_into_typed_addresses(tmp_path):
    s = load_scenario(write(tmp_path, TEXT))
    assert s.name == "pair" and s.step == 0.5 and s.n_steps == 4 and s.algorithm == "gauss-seidel"
    assert s.connections == ((S("src.y"), S("body.f_a")),)
    assert s.record == (S("body.flange_a.s"),)
    assert s.metrics == {"reach": Metric(S("body.flange_a.s"), "max", over=S("src.y"))}
    assert s.plots == (Panel("force", (S("src.y"), S("body.f_a"))),)
    assert s.instances["src"] == Instance("src", "SignalSource", {"amplitude": 2.0})
    assert s.instances["body"].every == 2
    assert s.recorded() == [S("body.flange_a.s"), S("src.y"), S("body.f_a")]


def test_set_is_parsed_at_the_edge_and_applied_by_with_values(tmp_path):
    s = load_scenario(write(tmp_path, TEXT), ["src.amplitude=3", "body.k = 150"])
    assert s.instances["src"].parameters == {"amplitude": 3.0}
    assert s.instances["body"].parameters == {"k": 150.0}
    direct = with_values(load_scenario(write(tmp_path, TEXT)),
                         {ParamRef("src", "amplitude"): 3, ParamRef("body", "k"): 150.0,
                          ParamRef("ghost", "k"): 1.0})  # an instance not there: skipped
    assert direct.instances == s.instances


@pytest.mark.parametrize("text, message", [
    ("src", "--set 'src' is not of the form instance.parameter=value"),
    ("src.=1", "--set 'src.=1' is not of the form instance.parameter=value"),
    ("ghost.k=1", "--set 'ghost.k=1': no instance 'ghost' (instances: src, body)"),
    ("src.k=x", "--set 'src.k=x': 'x' is not a number"),
    ("src.k=nan", "--set 'src.k=nan': the value must be finite"),
])
def test_a_bad_set_is_named(tmp_path, text, message):
    s = load_scenario(write(tmp_path, TEXT))
    problems = []
    assert apply_overrides(s, [text], problems) == s
    assert problems == [message]


@pytest.mark.parametrize("change, message", [
    (('[["src.y", "body.f_a"]]', '[["src", "body.f_a"]]'),
     "connection ['src', 'body.f_a'] is not a pair [\"src.output\", \"dst.input\"]"),
    (('record = ["body.flange_a.s"]', 'record = ["time"]'),
     "'record' must be a list of \"instance.variable\" strings"),
    (('over = "src.y"', 'over = "y"'), "metric 'reach' needs signal = \"inst.var\""),
    (('signals = ["src.y", "body.f_a"]', 'signals = ["src.y", 3]'),
     "plot panel {'title': 'force', 'signals': ['src.y', 3]} needs a 'signals' list"),
    (('every = 2', 'every = 0'), "instance 'body': every = 0 must be a whole number"),
])
def test_every_problem_is_collected_and_named(tmp_path, change, message):
    path = write(tmp_path, 'unknown = 1\n' + TEXT.replace(*change))
    with pytest.raises(UserError) as err:
        load_scenario(path)
    assert str(err.value).startswith(f"scenario {path} has 2 problem(s): ")
    assert message in str(err.value) and "unknown key 'unknown'" in str(err.value)


def test_times_are_checked_once_the_file_parses(tmp_path):
    path = write(tmp_path, TEXT.replace("stop_time = 2.0", "stop_time = 2.2"))
    with pytest.raises(UserError, match=r"has 1 problem\(s\): stop_time - start_time = 2.2 s is "
                                        r"not a whole number of steps of 0.5 s"):
        load_scenario(path)


def test_stop_time_replaces_the_files_and_must_be_finite(tmp_path):
    assert load_scenario(write(tmp_path, TEXT), stop_time=1.0).n_steps == 2
    with pytest.raises(UserError, match="--stop-time inf is not a finite number"):
        load_scenario(write(tmp_path, TEXT), stop_time=math.inf)


def test_every_shipped_scenario_loads_with_its_signals_typed():
    for path in sorted(SCENARIOS.glob("*.toml")):
        if "[sweep]" in path.read_text():  # a sweep file names its scenario
            continue
        s = load_scenario(path)
        assert isinstance(s, Scenario)
        for sig in [*(x for pair in s.connections for x in pair), *s.recorded()]:
            assert isinstance(sig, Signal) and sig.instance in s.instances, (path.name, sig)
