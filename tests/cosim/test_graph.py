"""musclesim.cosim.graph: a scenario's data flow on hand-made scenarios, each drawn in its test.

Chain and loop used below::

    chain:  a --y/u--> b --y/u--> c
    loop:   a --y/u--> b --y/u--> c --y/r--> b   (b and c in a cycle), d alone
"""
import dataclasses

import pytest

from musclesim.cosim import Instance, Link, Scenario, Signal

S = Signal.parse


def scenario(names, pairs):
    return Scenario("hand-made", None, {n: Instance(n, "C") for n in names},
                    tuple((S(a), S(b)) for a, b in pairs), step=1.0, stop_time=1.0,
                    record=(S("a.y"),))


CHAIN = scenario("abc", [("a.y", "b.u"), ("b.y", "c.u")])
LOOP = scenario("abcd", [("a.y", "b.u"), ("b.y", "c.u"), ("c.y", "b.r")])


def test_links_keep_the_signals_and_name_their_ends():
    link = CHAIN.graph.links[0]
    assert link == Link(S("a.y"), S("b.u"))
    assert (link.source, link.output, link.target, link.input) == ("a", "y", "b", "u")


def test_the_graph_is_built_once_per_scenario_and_anew_for_a_changed_one():
    assert CHAIN.graph is CHAIN.graph
    changed = dataclasses.replace(CHAIN, connections=CHAIN.connections[:1])
    assert changed.graph is not CHAIN.graph and len(changed.graph.links) == 1


def test_order_puts_sources_first_and_asks_where_a_cycle_is_entered():
    assert CHAIN.graph.order(CHAIN.graph.edges(), pick_in_cycle=None) == ["a", "b", "c"]
    backwards = scenario("cba", [("a.y", "b.u"), ("b.y", "c.u")])
    assert backwards.graph.order(backwards.graph.edges(), None) == ["a", "b", "c"]
    asked = []

    def pick(remaining):
        asked.append(list(remaining))
        return remaining[-1]

    assert LOOP.graph.order(LOOP.graph.edges(), pick) == ["a", "d", "c", "b"]
    assert asked == [["b", "c"]]  # only once a, then d, were placed


def test_edges_keep_the_links_whose_input_feeds_through():
    edges = LOOP.graph.edges(lambda target, var: var == "r")
    assert edges == {("c", "b")}
    assert LOOP.graph.edges() == {("a", "b"), ("b", "c"), ("c", "b")}


def test_upstream_downstream_and_a_cut():
    g = LOOP.graph
    assert g.upstream({"c"}) == {"a", "b", "c"}
    assert g.upstream({"c"}, cut={S("b.y")}) == {"c"}
    assert g.upstream({"d"}) == {"d"}
    assert g.downstream({"a"}) == {"a", "b", "c"} and g.downstream({"c"}) == {"b", "c"}


def test_fed_within_and_inputs_of():
    g = LOOP.graph
    assert g.fed_within({"b", "c"}) == set()  # a feeds b
    assert g.fed_within({"a", "b", "c", "d"}) == {"a", "b", "c", "d"}
    assert g.inputs_of({"b"}) == {S("b.u"), S("b.r")}
    assert g.source_of() == {S("b.u"): S("a.y"), S("c.u"): S("b.y"), S("b.r"): S("c.y")}


def test_restrict_keeps_the_links_inside_but_those_into_replayed_inputs():
    part = LOOP.graph.restrict({"b", "c"}, replayed={S("b.r")}, record=[S("c.y")])
    assert set(part.instances) == {"b", "c"}
    assert part.connections == ((S("b.y"), S("c.u")),)
    assert part.record == (S("c.y"),) and part.metrics == {} and part.plots == ()
    assert part.graph.links == (Link(S("b.y"), S("c.u")),)


@pytest.mark.parametrize("start", [set(), {"a"}])
def test_closure_of_nothing_is_nothing_and_a_start_reaches_itself(start):
    assert CHAIN.graph.upstream(start) == start
