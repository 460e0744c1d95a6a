"""Capstan multiplier (§capstan-multiplier): one SMA wire folded over fixed capstans into segments.

Segments are numbered from the fixed clamp (1) to the load end (n). Contact j sits between
segments j and j + 1 and the wire sweeps the angle theta_j over it. With the load's tension f at
the load end, the capstan equation (§capstan-multiplier) steps the tension up toward the clamp:

    f_n = f,   f_i = f_{i+1} exp(mu_f theta_i),   sigma_i = f_i / A

Each segment is a lumped SMA wire of its own (§thermal-model thermal model, §preisach modified
Preisach model on the shared hypersurface, each with its own memory and its own stress). The wire is
one electrical element: the segments are in series, so under voltage drive segment i sees
u_i = u R_i / sum R (resistances at the start of the step, as the straight wire's) and under
current drive the same current. The end displacement is the sum of the segments' contractions,

    s = sum_i eps_i L_i.

The cores are the straight wire's (`musclesim.components.sma.thermal`, `.preisach`; its thermal
submodel `submodels.Lumped`, no end zones); with one segment and mu_f = 0 a step is the SmaWire
FMU's step exactly. Equations and every assumption:
§capstan-multiplier (docs/model/multiplier.md).
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

from musclesim.components.checks import require
from musclesim.components.sma import submodels, thermal
from musclesim.components.sma.preisach import PreisachModel
from musclesim.components.sma.surface import Hypersurface, clamp
from musclesim.fmu import declare

MAX_SEGMENTS = 6  # variables the FMU declares per segment (§capstan-multiplier suggests three)
WRAP = math.pi  # rad, sweep per turning tube: a ratio 1.060-1.085 fits about pi
#                 (§capstan-multiplier)
MU_F = 0.0237  # wire on PTFE (§capstan-multiplier: 0.0237 +/- 0.0037)
LENGTH = 0.214  # m, the multiplier wire (§capstan-multiplier)


@dataclass(frozen=True)
class CapstanParams:
    """Geometry of the fold and the wire (defaults §capstan-multiplier; material §sma-material via
    `wire`). Each FMU parameter is declared once here (`declare`), the wire's in
    `thermal.ThermalParams`.

    ``segment_lengths``: one entry per segment [m]; 0 (or an empty tuple) = an equal share of
    what the other entries leave of ``length``. ``wraps``: one angle [rad] per contact (n - 1);
    empty = pi at each. ``composition_shift`` is the diagnosis's effect "composition difference",
    ``contact_conductance`` (the heat each contact's PTFE tube draws per kelvin of the wire's
    excess temperature) its effect "capstan heat loss".
    """

    length: float = declare(LENGTH, "m", "Total wire length (the study: 214 mm)",
                            source="§capstan-multiplier")
    n_segments: int = declare(3, "1", f"Number of segments, 1..{MAX_SEGMENTS} (the study's "
                              "sensing, one thermocouple per segment, suggests three over two "
                              "turning tubes)", source="§capstan-multiplier", type="Integer")
    segment_lengths: tuple[float, ...] = ()  # the FMU's segment_length[i]
    wraps: tuple[float, ...] = ()  # the FMU's wrap[j]
    mu_f: float = declare(MU_F, "1", "Friction coefficient of the wire on the capstans (the "
                          "study: 0.0237 +/- 0.0037, wire on PTFE)", source="§capstan-multiplier",
                          effect=(0.0, 0.1))
    composition_shift: float = declare(0.0, "K", "Effect, 0 = off: composition difference, the "
                                       "wire's hysteresis sees T - shift and transforms shift "
                                       "hotter", source="§capstan-multiplier, §named-effects",
                                       effect=(-10.0, 10.0))
    contact_conductance: float = declare(0.0, "W/K", "Effect, 0 = off: capstan heat loss, the "
                                         "heat conductance of each wire-on-PTFE contact to the "
                                         "room, shared by the two segments it joins",
                                         source="§capstan-multiplier, §named-effects",
                                         effect=(0.0, 0.01))
    wire: thermal.ThermalParams = field(default_factory=thermal.ThermalParams)

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, positive=("length",), non_negative=("mu_f", "contact_conductance"))
        if not (self.n_segments == int(self.n_segments) and 1 <= self.n_segments <= MAX_SEGMENTS):
            raise ValueError(f"n_segments must be an integer within 1..{MAX_SEGMENTS} "
                             f"(got {self.n_segments!r})")
        if len(self.segment_lengths) not in (0, self.n_segments):
            raise ValueError(f"segment_lengths needs one entry per segment ({self.n_segments}), "
                             f"got {len(self.segment_lengths)}")
        if any(not (x >= 0 and math.isfinite(x)) for x in self.segment_lengths):
            raise ValueError(f"segment_lengths must be non-negative [m] (got "
                             f"{list(self.segment_lengths)})")
        if len(self.wraps) not in (0, self.n_segments - 1):
            raise ValueError(f"wraps needs one angle per contact ({self.n_segments - 1}), "
                             f"got {len(self.wraps)}")
        if any(not (w >= 0 and math.isfinite(w)) for w in self.wraps):
            raise ValueError(f"wraps must be non-negative angles [rad] (got {list(self.wraps)})")
        if not math.isfinite(self.composition_shift):
            raise ValueError(f"composition_shift must be finite (got {self.composition_shift!r})")
        segment_lengths(self)  # the lengths must add up
        self.wire.check()


def segment_lengths(p: CapstanParams) -> list[float]:
    """Length [m] of each segment of the fold `p`, clamp first: given entries as they are, the
    zeros sharing the rest of ``length`` equally.

    Examples
    --------
    >>> segment_lengths(CapstanParams(length=0.5, n_segments=3, segment_lengths=(0.1, 0.0, 0.0)))
    [0.1, 0.2, 0.2]
    """
    n = int(p.n_segments)
    given = list(p.segment_lengths) or [0.0] * n
    free = [i for i, x in enumerate(given) if x == 0]
    rest = p.length - math.fsum(given)
    if free:
        if not rest > 0:
            raise ValueError(f"segment_lengths leave no length for the segments set to 0 "
                             f"(length {p.length:g} m, given {math.fsum(given):g} m)")
        share = rest / len(free)
        given = [share if i in free else x for i, x in enumerate(given)]
    elif abs(rest) > 1e-9 * p.length:
        raise ValueError(f"segment_lengths add up to {math.fsum(given):g} m, not the wire's "
                         f"length {p.length:g} m")
    return given


def contact_wraps(p: CapstanParams) -> list[float]:
    """Wrap angle [rad] of each contact of the fold `p`, between segments j and j + 1."""
    return list(p.wraps) if p.wraps else [WRAP] * (int(p.n_segments) - 1)


def tension_ratios(p: CapstanParams) -> list[float]:
    """Tension of each segment of the fold `p` over the load's tension, clamp first: exp(mu_f sum
    of the wraps between it and the load end); exactly 1.0 for the load-end segment and when mu_f =
    0.

    Examples
    --------
    >>> [round(r, 4) for r in tension_ratios(CapstanParams(mu_f=0.0237))]
    [1.1606, 1.0773, 1.0]
    """
    wraps = contact_wraps(p)
    n = int(p.n_segments)
    return [math.exp(p.mu_f * math.fsum(wraps[i:])) if p.mu_f else 1.0 for i in range(n)]


def segment_h(p: CapstanParams, lengths: Sequence[float]) -> list[float]:
    """Convection coefficient [W/(m^2 K)] of each segment of the fold `p` (of `lengths` [m]) with
    its contacts' heat loss lumped
    into it: h + G_i / (pi d L_i), G_i the half conductances of the contacts at its ends.

    A contact draws ``contact_conductance`` (T - T_amb) from the wire where it lies on a tube;
    the segments are lumped, so that heat is taken from the two segments the contact joins,
    half each, as if spread along them (§capstan-multiplier).

    >>> p = CapstanParams(contact_conductance=2e-3)
    >>> [round(h, 1) for h in segment_h(p, segment_lengths(p))]
    [135.1, 170.3, 135.1]
    """
    n, h, d = len(lengths), p.wire.h, p.wire.diameter
    out = []
    for i, L in enumerate(lengths):
        contacts = (i > 0) + (i < n - 1)
        out.append(h + 0.5 * contacts * p.contact_conductance / (math.pi * d * L))
    return out


def segment_voltages(u: float, resistances: Sequence[float]) -> list[float]:
    """Voltage [V] across each of the series segments of `resistances` [Ohm]: `u` R_i / sum R (u
    itself for one)."""
    total = sum(resistances)
    return [u * (r / total) for r in resistances]


class Segment:
    """One segment's state: temperature [C], hysteresis memory, martensite fraction, strain."""

    def __init__(self, params: thermal.ThermalParams, surface: Hypersurface) -> None:
        """A segment of thermal `params` (this segment's length) on the hysteresis `surface`."""
        self.p = params  # ThermalParams with this segment's length
        # the straight wire's thermal submodel, without its effects: lumped, ends none
        self.thermal = submodels.Lumped()
        self.surface = surface
        self.model = PreisachModel(surface)
        self.T_C = 0.0
        self.xi = 1.0
        self.eps = 0.0
        self.sigma = 0.0
        self._eps_max_at: tuple[float | None, float] = (None, 0.0)

    def eps_max(self, sigma: float) -> float:
        """F(a0, b0; `sigma`): the strain of a fully transformed segment (one F per new stress)."""
        if self._eps_max_at[0] != sigma:
            s = self.surface
            self._eps_max_at = (sigma, s.F(s.t_hi, s.t_lo, sigma))
        return self._eps_max_at[1]


class Multiplier:
    """The folded wire, stepped as the SmaWire FMU steps a straight wire (inputs held over a step).

    ``start(T_init, f, t)`` sets every segment to T_init [C], fully martensitic; ``step(u,
    T_amb, f, t, dt)`` advances all segments over [t, t + dt] with the heating input u (V or A per
    ``wire.drive``), ambient T_amb [C] and the load's tension f [N]. Stresses outside the data
    set's stresses are clamped with one `RangeWarning` per segment (a single-surface data set
    takes any stress).

    Examples
    --------
    >>> from musclesim.components.sma import datasets
    >>> m = Multiplier(CapstanParams(), datasets.surface(1))
    >>> m.start(20.0, 1.47)
    >>> for k in range(500):
    ...     m.step(6.0, 20.0, 1.47, k * 2e-3, 2e-3)
    >>> round(m.displacement() * 1e3, 2), [round(s.T_C) for s in m.segments]
    (8.33, [138, 139, 139])
    """

    def __init__(self, params: CapstanParams, surface: Hypersurface) -> None:
        """The multiplier of `params` (checked here), its wire's segments on the `surface`."""
        params.check()
        self.params = params
        self.surface = surface
        self.lengths = segment_lengths(params)
        # length shares, so that one segment's mean is its own value exactly (share 1.0)
        self.shares = [L / params.length for L in self.lengths]
        self.ratios = tension_ratios(params)
        self.area = thermal.cross_section(params.wire)
        self.segments = [Segment(_with_length(params.wire, L, h), surface)
                         for L, h in zip(self.lengths, segment_h(params, self.lengths))]
        self._warned: set[str] = set()
        self.power = 0.0

    def stresses(self, f: float, t: float | None = None) -> list[float]:
        """Stress [Pa] of each segment under the load's tension `f` [N] at `t` [s], as the
        hysteresis takes it: clamped to the data set's stresses, warned once per segment."""
        s = self.surface
        out = []
        for i, r in enumerate(self.ratios, start=1):
            sigma = f * r / self.area
            if len(s.stresses) > 1 and not s.s_lo <= sigma <= s.s_hi:
                sigma = clamp(self._warned, f"stress of segment {i}", sigma, s.s_lo, s.s_hi,
                              "Pa", t)
            out.append(sigma)
        return out

    def start(self, T_init: float, f: float, t: float = 0.0, u: float = 0.0) -> None:
        """Every segment at `T_init` [C], all-off memory then T_init (a new wire heated to it),
        under the load `f` [N] at `t` [s], the power that of the input `u`."""
        for seg, sigma, r in zip(self.segments, self.stresses(f, t), self.ratios):
            seg.T_C = T_init
            seg.model = PreisachModel(self.surface)
            eps = seg.model.reset(self._seen(T_init), sigma, t)
            seg.xi = thermal.martensite_fraction(eps, seg.eps_max(sigma))
            seg.eps = eps
            seg.sigma = f * r / self.area
        self.power = self.joule_power(u)

    def step(self, u: float, T_amb: float, f: float, t: float, dt: float) -> None:
        """Advance every segment over [`t`, `t` + `dt`] [s] with `u`, `T_amb` [C] and `f` [N]
        held."""
        sigmas = self.stresses(f, t)
        drives = self._drives(u)
        self.power = self.joule_power(u)
        for seg, sigma, ui in zip(self.segments, sigmas, drives):
            eps_max = seg.eps_max(sigma)
            T_new = seg.thermal.step(seg.T_C, thermal.ThermalInputs(ui, T_amb, seg.xi), dt, seg.p)
            eps = seg.model.step(self._seen(T_new), sigma, t + dt)
            seg.xi = thermal.martensite_fraction(eps, eps_max)
            seg.eps = eps
            seg.T_C = T_new
        for seg, r in zip(self.segments, self.ratios):
            seg.sigma = f * r / self.area

    def _drives(self, u):
        """Each segment's electrical input: its share of the voltage, or the series current."""
        if self.params.wire.drive == "current":
            return [u] * len(self.segments)
        return segment_voltages(u, [thermal.resistance(s.xi, s.p) for s in self.segments])

    def _seen(self, T):
        """Temperature [C] the hysteresis sees: composition-shifted, saturated at the grid."""
        return min(max(T - self.params.composition_shift, self.surface.t_lo), self.surface.t_hi)

    def resistance(self) -> float:
        """Series resistance [Ohm] of the segments at their present martensite fractions."""
        return sum(thermal.resistance(s.xi, s.p) for s in self.segments)

    def joule_power(self, u: float) -> float:
        """Joule power [W] of input `u` over all segments at their present resistances."""
        return sum(thermal.joule_power(ui, s.xi, s.p)
                   for s, ui in zip(self.segments, self._drives(u)))

    def displacement(self) -> float:
        """End displacement [m]: the sum of the segments' contractions eps_i L_i."""
        return sum(s.eps * L for s, L in zip(self.segments, self.lengths))

    def mean_temperature(self) -> float:
        """Length-weighted mean temperature [C] of the segments."""
        return sum(s.T_C * w for s, w in zip(self.segments, self.shares))

    def mean_strain(self) -> float:
        """Length-weighted mean strain of the segments (the displacement over the length)."""
        return sum(s.eps * w for s, w in zip(self.segments, self.shares))


def _with_length(wire: thermal.ThermalParams, length: float, h: float) -> thermal.ThermalParams:
    """`wire`'s ThermalParams with another length and convection coefficient."""
    fields = {name: getattr(wire, name) for name in wire.__dataclass_fields__}
    fields.update(length=length, h=h)
    return thermal.ThermalParams(**fields)
