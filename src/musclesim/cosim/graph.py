"""A scenario's data flow as a graph: its instances and connections, each signal parsed once.

The master orders the exchange and the stepping of instances on it; the diagnosis cuts units out
of it (an instance and what feeds it, the scenario restricted to them, what one instance can
change). Every question about which instance feeds which is answered here, once.
"""
from dataclasses import dataclass, replace

from musclesim.cosim.scenario import split_signal


@dataclass(frozen=True)
class Link:
    """One connection: output `src` of instance `source` feeds input `dst` of `target`."""

    src: str
    dst: str
    source: str
    output: str
    target: str
    input: str


class Graph:
    """The instances of a `Scenario` and the links between them.

    Examples
    --------
    >>> from musclesim.cosim.scenario import Instance, Scenario
    >>> s = Scenario("s", None, {n: Instance(n, "C") for n in "abc"},
    ...              (("a.y", "b.u"), ("b.y", "c.u")), step=1.0, stop_time=1.0)
    >>> g = Graph(s)
    >>> sorted(g.upstream({"c"}))
    ['a', 'b', 'c']
    >>> sorted(g.upstream({"c"}, cut={"b.y"}))
    ['c']
    >>> sorted(g.downstream({"b"}))
    ['b', 'c']
    >>> sorted(g.fed_within({"b", "c"})), sorted(g.fed_within({"a", "b"}))
    ([], ['a', 'b'])
    """

    def __init__(self, scenario):
        self.scenario = scenario
        self.instances = tuple(scenario.instances)
        self.links = tuple(Link(src, dst, *split_signal(src), *split_signal(dst))
                           for src, dst in scenario.connections)

    def edges(self, feedthrough=None):
        """{(source, target)} of every link, or of the links whose input `feedthrough(target,
        input)` says an output of the target depends on at the same instant."""
        return {(k.source, k.target) for k in self.links
                if feedthrough is None or feedthrough(k.target, k.input)}

    def order(self, edges, pick_in_cycle):
        """The instances ordered so that each edge's source comes first; in a cycle,
        `pick_in_cycle(remaining)` chooses the next one."""
        incoming = {n: {a for a, b in edges if b == n and a != n} for n in self.instances}
        order, remaining = [], list(self.instances)
        while remaining:
            ready = [n for n in remaining if not incoming[n] & set(remaining)]
            nxt = ready[0] if ready else pick_in_cycle(remaining)
            order.append(nxt)
            remaining.remove(nxt)
        return order

    def upstream(self, start, cut=()):
        """`start` and every instance that feeds it, directly or not, through links whose
        signals (output or input) are not in `cut` (measured signals end the closure)."""
        return _closure(start, [(k.target, k.source) for k in self.links
                                if k.src not in cut and k.dst not in cut])

    def downstream(self, start):
        """`start` and every instance it feeds, directly or not."""
        return _closure(start, [(k.source, k.target) for k in self.links])

    def fed_within(self, candidates):
        """The largest part of `candidates` that no instance outside it feeds: without those an
        instance outside feeds, directly or through others of `candidates`."""
        candidates = set(candidates)
        inner = [(k.source, k.target) for k in self.links if k.target in candidates]
        fed = {b for a, b in inner if a not in candidates}
        return candidates - _closure(fed, inner)

    def inputs_of(self, instances):
        """The connected inputs of `instances`."""
        return {k.dst for k in self.links if k.target in instances}

    def restrict(self, keep, replayed=(), record=()):
        """The scenario reduced to the instances `keep`: the links between them, but those into
        a `replayed` input; recording `record`, no metrics, no plots."""
        links = tuple((k.src, k.dst) for k in self.links if k.source in keep and k.target in keep
                      and k.dst not in replayed)
        s = self.scenario
        return replace(s, instances={n: i for n, i in s.instances.items() if n in keep},
                       connections=links, record=tuple(record), metrics={}, plots=())


def _closure(start, edges):
    """`start` and every node reached from it along `edges`, pairs (from, to)."""
    reach, todo = set(start), list(start)
    while todo:
        node = todo.pop()
        for a, b in edges:
            if a == node and b not in reach:
                reach.add(b)
                todo.append(b)
    return reach
