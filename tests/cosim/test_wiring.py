"""musclesim.cosim.wiring: a scenario's wiring checked against its FMUs' model descriptions, every
problem collected and raised once by the master, each naming the signal as the file writes it."""
import dataclasses

import numpy as np
import pytest

from musclesim.cosim import Instance, Master, Scenario, Signal, scenario
from musclesim.errors import UserError

from conftest import SCENARIOS

S = Signal.parse


def test_every_wiring_problem_is_named_at_once(fmu_dir):
    """source --y--> body (a Real output into an output, a unit mismatch, an unknown variable,
    an input fed twice, an unknown instance, a parameter set on an output): one error lists all."""
    s = Scenario("hand-made", SCENARIOS / "hand-made.toml",
                 {"src": Instance("src", "SignalSource"),
                  "body": Instance("body", "CrawlerBody", {"x_cm": 1.0})},
                 ((S("src.y"), S("body.x_cm")), (S("src.y"), S("body.f_a")),
                  (S("src.y"), S("body.f_a")), (S("src.nothing"), S("body.f_b")),
                  (S("ghost.y"), S("body.f_b"))),
                 step=0.01, stop_time=0.1)
    with pytest.raises(UserError) as err:
        Master(s, fmu_dir)
    message = str(err.value)
    assert message.startswith(f"scenario {s.path}: ")
    assert "connection src.y -> body.x_cm: body.x_cm is an output, not an input" in message
    assert "input body.f_a is connected twice (from src.y and src.y)" in message
    assert "connection source 'src.nothing': SignalSource has no variable 'nothing'" in message
    assert "connection source 'ghost.y': no instance 'ghost'" in message
    assert "body.x_cm is an output, not a parameter or an input" in message


def test_replayed_inputs_are_checked(fmu_dir):
    s = scenario.load(SCENARIOS / "sma-bench-tracking.toml", stop_time=1.0)
    n = s.n_steps + 1
    with pytest.raises(UserError) as err:
        Master(s, fmu_dir, {S("wire.u"): np.zeros(n), S("wire.T"): np.zeros(n),
                            S("wire.flange.f"): np.zeros(3)})
    msg = str(err.value)
    assert "replayed input wire.u is also connected (from pid.y)" in msg
    assert "replayed input wire.T is an output, not an input" in msg
    assert "replayed input wire.flange.f has 3 values, not one per communication point (51)" in msg



def test_a_renamed_port_is_refused_with_its_new_name(fmu_dir):
    """The crawler body's blocks took MSL's flange_a / flange_b: an old scenario's flange1 is
    named in the message, not listed among unknown variables."""
    s = scenario.load(SCENARIOS / "crawler-ideal.toml", stop_time=0.1)
    s = dataclasses.replace(s, record=(S("body.flange1.s"),))
    with pytest.raises(UserError, match=r"recorded signal 'body.flange1.s': CrawlerBody's "
                                        r"flange1.s has been renamed flange_a.s"):
        Master(s, fmu_dir)
