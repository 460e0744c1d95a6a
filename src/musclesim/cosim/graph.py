"""A scenario's data flow as a graph: its instances and connections (typed `Signal` pairs).

The master orders the exchange and the stepping of instances on it; the diagnosis cuts units out
of it (an instance and what feeds it, the scenario restricted to them, what one instance can
change). Every question about which instance feeds which is answered here, once. A scenario
holds its graph (`Scenario.graph`, built once per scenario object).
"""
from __future__ import annotations

from collections.abc import Callable, Collection, Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any, ClassVar, Generic, Protocol, TypeVar

from musclesim.cosim.address import Signal


class Wired(Protocol):
    """What a graph is made of: a dataclass (a `musclesim.cosim.Scenario`) with named instances
    and connections between their signals."""

    __dataclass_fields__: ClassVar[dict[str, Any]]

    @property
    def instances(self) -> Mapping[str, Any]: ...

    @property
    def connections(self) -> tuple[tuple[Signal, Signal], ...]: ...


W = TypeVar("W", bound=Wired)


@dataclass(frozen=True)
class Link:
    """One connection: the output `src` (of the instance `source`) feeds the input `dst` (of
    `target`)."""

    src: Signal
    dst: Signal

    @property
    def source(self) -> str:
        """The instance whose output feeds the link."""
        return self.src.instance

    @property
    def output(self) -> str:
        """The output of `source` the link reads."""
        return self.src.variable

    @property
    def target(self) -> str:
        """The instance whose input the link sets."""
        return self.dst.instance

    @property
    def input(self) -> str:
        """The input of `target` the link sets."""
        return self.dst.variable


class Graph(Generic[W]):
    """The instances of a scenario and the links between them.

    Examples
    --------
    >>> from musclesim.cosim.scenario import Instance, Scenario
    >>> S = Signal.parse
    >>> s = Scenario("s", None, {n: Instance(n, "C") for n in "abc"},
    ...              ((S("a.y"), S("b.u")), (S("b.y"), S("c.u"))), step=1.0, stop_time=1.0)
    >>> g = s.graph
    >>> sorted(g.upstream({"c"}))
    ['a', 'b', 'c']
    >>> sorted(g.upstream({"c"}, cut={S("b.y")}))
    ['c']
    >>> sorted(g.downstream({"b"}))
    ['b', 'c']
    >>> sorted(g.fed_within({"b", "c"})), sorted(g.fed_within({"a", "b"}))
    ([], ['a', 'b'])
    """

    def __init__(self, scenario: W) -> None:
        """The graph of `scenario`'s instances and connections."""
        self.scenario = scenario
        self.instances: tuple[str, ...] = tuple(scenario.instances)
        self.links: tuple[Link, ...] = tuple(Link(src, dst) for src, dst in scenario.connections)

    def edges(self, feedthrough: Callable[[str, str], object] | None = None
              ) -> set[tuple[str, str]]:
        """{(source, target)} of every link, or of the links whose input `feedthrough`, called as
        ``feedthrough(target, input)``, says an output of the target depends on at the same
        instant."""
        return {(k.source, k.target) for k in self.links
                if feedthrough is None or feedthrough(k.target, k.input)}

    def order(self, edges: Collection[tuple[str, str]],
              pick_in_cycle: Callable[[list[str]], str]) -> list[str]:
        """The instances ordered so that each of the `edges`' source comes first; in a cycle,
        `pick_in_cycle` (called with the instances remaining) chooses the next one."""
        incoming = {n: {a for a, b in edges if b == n and a != n} for n in self.instances}
        order: list[str] = []
        remaining = list(self.instances)
        while remaining:
            ready = [n for n in remaining if not incoming[n] & set(remaining)]
            nxt = ready[0] if ready else pick_in_cycle(remaining)
            order.append(nxt)
            remaining.remove(nxt)
        return order

    def upstream(self, start: Iterable[str], cut: Collection[Signal] = ()) -> set[str]:
        """`start` and every instance that feeds it, directly or not, through links whose
        signals (output or input) are not in `cut` (measured signals end the closure)."""
        return _closure(start, [(k.target, k.source) for k in self.links
                                if k.src not in cut and k.dst not in cut])

    def downstream(self, start: Iterable[str]) -> set[str]:
        """`start` and every instance it feeds, directly or not."""
        return _closure(start, [(k.source, k.target) for k in self.links])

    def fed_within(self, candidates: Iterable[str]) -> set[str]:
        """The largest part of `candidates` that no instance outside it feeds: without those an
        instance outside feeds, directly or through others of `candidates`."""
        inside = set(candidates)
        inner = [(k.source, k.target) for k in self.links if k.target in inside]
        fed = {b for a, b in inner if a not in inside}
        return inside - _closure(fed, inner)

    def inputs_of(self, instances: Collection[str]) -> set[Signal]:
        """The connected inputs of `instances`."""
        return {k.dst for k in self.links if k.target in instances}

    def source_of(self) -> dict[Signal, Signal]:
        """{input: the output that feeds it} of every link."""
        return {k.dst: k.src for k in self.links}

    def restrict(self, keep: Collection[str], replayed: Collection[Signal] = (),
                 record: Sequence[Signal] = ()) -> W:
        """The scenario reduced to the instances `keep`: the links between them, but those into
        a `replayed` input; recording `record`, no metrics, no plots."""
        links = tuple((k.src, k.dst) for k in self.links if k.source in keep and k.target in keep
                      and k.dst not in replayed)
        s = self.scenario
        return replace(s, instances={n: i for n, i in s.instances.items() if n in keep},
                       connections=links, record=tuple(record), metrics={}, plots=())


def _closure(start: Iterable[str], edges: list[tuple[str, str]]) -> set[str]:
    """`start` and every node reached from it along `edges`, pairs (from, to)."""
    reach, todo = set(start), list(start)
    while todo:
        node = todo.pop()
        for a, b in edges:
            if a == node and b not in reach:
                reach.add(b)
                todo.append(b)
    return reach
