"""The crawler's FMU slaves (components/crawler/slaves.py): the friction block's slip and
contact at the start of each step, its incline and time effects, the body's incline."""
import math

import pytest

from musclesim.components.crawler.slaves import CrawlerBody, FrictionBlock

from component_runs import set_reals, started


def test_block_reports_slip_from_velocity_and_contact_at_the_start_of_each_step():
    """The FMU slave sums |v| dt over the steps that start high and sliding (hand sum)."""
    block, vr = started(FrictionBlock)
    for k, (u, v) in enumerate([(1.0, 0.01), (1.0, -0.03), (0.0, 0.05), (1.0, 5e-4), (1.0, 0.02)]):
        set_reals(block, vr, {"u": u, "flange.v": v})
        block.do_step(0.1 * k, 0.1)
    assert block.get_real([vr["slip"]])[0] == pytest.approx((0.01 + 0.03 + 0.02) * 0.1, rel=1e-15)
    # with a switching time the contact reaches 0.5 only at the start of the second step
    block, vr = started(FrictionBlock, t_switch=0.2)
    set_reals(block, vr, {"u": 1.0, "flange.v": 0.01})
    slips = []
    for k in range(3):
        block.do_step(0.1 * k, 0.1)
        slips.append(block.get_real([vr["slip"]])[0])
    assert slips == [0.0, pytest.approx(1e-3, rel=1e-15), pytest.approx(2e-3, rel=1e-15)]


def test_block_applies_incline_and_time_to_the_high_static_coefficient():
    """A stuck high-friction block holds up to the scaled mu_s at t = 1 s, then breaks away."""
    theta = 0.2
    block, vr = started(FrictionBlock, bending=1.5, mu_decay=0.05)
    set_reals(block, vr, {"u": 1.0, "theta": theta, "flange.N": 1.0})
    for k in range(10):
        block.do_step(0.1 * k, 0.1)
    mu_s = 1.0 * (1 - 1.5 * theta) * math.exp(-0.05 * 1.0)
    for f_n, holds in ((0.999 * mu_s, True), (1.001 * mu_s, False)):
        set_reals(block, vr, {"flange.f_n": f_n})
        f, stuck = block.get_real([vr["flange.f"], vr["stuck"]])
        assert stuck == float(holds)
        assert f == (-f_n if holds else pytest.approx(-0.75 * mu_s, rel=1e-15))


def test_body_reports_its_incline_for_the_friction_blocks():
    body_slave, vr = started(CrawlerBody, theta=0.13)
    assert body_slave.get_real([vr["incline"]]) == [0.13]
