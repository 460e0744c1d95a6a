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

The cores are the straight wire's compiled ones (`musclesim.components.sma.thermal`'s lumped
step, no end zones; `.preisach`'s array memory), composed here into one compiled kernel
(`KERNEL`, on float64 arrays: layout at the ``P_*``, ``X_*`` and ``G_*`` slots); with one segment
and mu_f = 0 a step is the SmaWire FMU's step exactly. Equations and every assumption:
§capstan-multiplier (docs/model/multiplier.md).
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from musclesim.components.checks import require
from musclesim.components.sma import preisach, surface as hypersurface, thermal
from musclesim.components.sma.preisach import mem_reset, mem_step
from musclesim.components.sma.surface import (S_SHI, S_THI, S_TLO, Hypersurface, clamp, fmax,
                                              fmin, stress_in_range, surface_F)
from musclesim.components.sma.thermal import (TP_SIZE, joule_power_k,
                                              martensite_fraction_k, resistance_k, step_k)
from musclesim.fmu import Kernel, declare, jit

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
    excess temperature) its effect "capstan heat loss", ``source_resistance`` (in series with the
    wire under voltage drive) its effect "supply resistance" and ``stress_rise`` (how much hotter
    the wire transforms per pascal above the data set's highest stress) its effect "hysteresis
    above the data's stresses" (§pulse-gap).
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
                                       effect=(-10.0, 10.0), plausible="difference")
    contact_conductance: float = declare(0.0, "W/K", "Effect, 0 = off: capstan heat loss, the "
                                         "heat conductance of each wire-on-PTFE contact to the "
                                         "room, shared by the two segments it joins",
                                         source="§capstan-multiplier, §named-effects",
                                         effect=(0.0, 0.01))
    source_resistance: float = declare(0.0, "Ohm", "Effect, 0 = off: supply resistance, the "
                                       "source resistance in series with the wire under voltage "
                                       "drive (the supply's output, its leads and switch)",
                                       source="§pulse-gap, §named-effects", effect=(0.0, 3.0))
    stress_rise: float = declare(0.0, "K/Pa", "Effect, 0 = off: hysteresis above the data's "
                                 "stresses, how much hotter the wire transforms per pascal of a "
                                 "segment's stress above the data set's highest (0: the data's "
                                 "highest stress holds, clamped)",
                                 source="§pulse-gap, §named-effects", effect=(0.0, 1.5e-7))
    wire: thermal.ThermalParams = field(default_factory=thermal.ThermalParams)

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, positive=("length",), non_negative=("mu_f", "contact_conductance",
                                                          "source_resistance", "stress_rise"))
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
    """One segment's state as the kernel keeps it (a view of `Multiplier.kx`): temperature [C],
    martensite fraction, strain and stress [Pa]."""

    def __init__(self, params: thermal.ThermalParams, x: np.ndarray) -> None:
        """The segment of thermal `params` (this segment's length) whose state block is `x`."""
        self.p = params  # ThermalParams with this segment's length
        self.x = x

    @property
    def T_C(self) -> float:
        """Temperature [C]."""
        return float(self.x[G_T])

    @property
    def xi(self) -> float:
        """Martensite fraction."""
        return float(self.x[G_XI])

    @property
    def eps(self) -> float:
        """Strain (contraction / this segment's length)."""
        return float(self.x[G_EPS])

    @property
    def sigma(self) -> float:
        """Stress [Pa], capstan-scaled from the load end (unclamped)."""
        return float(self.x[G_SIGMA])


class Multiplier:
    """The folded wire, stepped as the SmaWire FMU steps a straight wire (inputs held over a step).

    ``start(T_init, f, t)`` sets every segment to T_init [C], fully martensitic; ``step(u,
    T_amb, f, t, dt)`` advances all segments over [t, t + dt] with the heating input u (V or A per
    ``wire.drive``), ambient T_amb [C] and the load's tension f [N]. Stresses outside the data
    set's stresses are clamped with one `RangeWarning` per segment (a single-surface data set
    takes any stress). The physics is the compiled kernel below (`start_k`, `step_k`): the state
    lives in its arrays ``kp`` (`pack`) and ``kx`` (`state`), which the FMU steps; the
    attributes read them.

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
        memory = preisach.memory()
        self.kp = pack(params, surface, len(memory))
        self.kx = state(self.kp, memory)
        self.segments = [Segment(_with_length(params.wire, L, h), block(self.kp, self.kx, i))
                         for i, (L, h) in enumerate(zip(self.lengths,
                                                        segment_h(params, self.lengths)))]
        self._warned: set[str] = set()

    @property
    def power(self) -> float:
        """Joule power [W] over the last step (input held, resistances at its start)."""
        return float(self.kx[X_P])

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
        start_fold(self.kp, self.kx, T_init, u, f, t)
        self.warn_clamps()

    def step(self, u: float, T_amb: float, f: float, t: float, dt: float) -> None:
        """Advance every segment over [`t`, `t` + `dt`] [s] with `u`, `T_amb` [C] and `f` [N]
        held."""
        step_fold(self.kp, self.kx, u, T_amb, f, t, dt)
        self.warn_clamps()

    def warn_clamps(self) -> None:
        """Warn (`clamp`'s `RangeWarning`, once per segment) of each segment's first stress
        clamp the kernel kept in its state, in the order of their times, as `stresses` warns."""
        s = self.surface
        met = sorted((seg.x[G_WARN_T], i) for i, seg in enumerate(self.segments, start=1)
                     if seg.x[G_WARN] == 1.0 and f"stress of segment {i}" not in self._warned)
        for t, i in met:
            sigma = float(self.segments[i - 1].x[G_WARN_SIGMA])
            clamp(self._warned, f"stress of segment {i}", sigma, s.s_lo, s.s_hi, "Pa", float(t))

    def resistance(self) -> float:
        """Series resistance [Ohm] of the segments at their present martensite fractions."""
        return float(resistance_sum(self.kp, self.kx))

    def joule_power(self, u: float) -> float:
        """Joule power [W] of input `u` over all segments at their present resistances."""
        return float(joule_power_sum(self.kp, self.kx, u))

    def displacement(self) -> float:
        """End displacement [m]: the sum of the segments' contractions eps_i L_i."""
        return float(weighted_sum(self.kp, self.kx, P_LENGTHS, G_EPS))

    def mean_temperature(self) -> float:
        """Length-weighted mean temperature [C] of the segments."""
        return float(weighted_sum(self.kp, self.kx, P_SHARES, G_T))

    def mean_strain(self) -> float:
        """Length-weighted mean strain of the segments (the displacement over the length)."""
        return float(weighted_sum(self.kp, self.kx, P_SHARES, G_EPS))


def _with_length(wire: thermal.ThermalParams, length: float, h: float) -> thermal.ThermalParams:
    """`wire`'s ThermalParams with another length and convection coefficient."""
    fields = {name: getattr(wire, name) for name in wire.__dataclass_fields__}
    fields.update(length=length, h=h)
    return thermal.ThermalParams(**fields)


# --- the compiled kernel (`musclesim.fmu.kernel`): `Multiplier`'s start and step on float64 arrays,
# operation for operation, so that it gives the same bits compiled or as Python -----------------
ZERO_C = 273.15  # K; the FMU speaks K, the cores C
INPUTS = ("u", "T_amb", "flange.f")
OUTPUTS = ("flange.s", "strain", "T", "stress", "R", "P") + tuple(
    f"segment[{i}].{v}" for i in range(1, MAX_SEGMENTS + 1) for v in ("T", "strain", "stress"))

# parameter slots (`pack`): the number of segments, the cross-section, the composition shift, the
# drive (1 = current), the size of one Preisach memory, the source resistance, the rise of the
# transformation above the data's stresses; then per segment (MAX_SEGMENTS slots each)
# the lengths, the length shares, the tension ratios, the thermal parameters (`thermal.pack`,
# TP_SIZE each); then the hysteresis surface (`surface.pack`) from P_HEAD
P_N, P_AREA, P_SHIFT, P_CURRENT, P_MEMORY, P_SOURCE_R, P_RISE = range(7)
P_LENGTHS = 7
P_SHARES = P_LENGTHS + MAX_SEGMENTS
P_RATIOS = P_SHARES + MAX_SEGMENTS
P_THERMAL = P_RATIOS + MAX_SEGMENTS
P_HEAD = P_THERMAL + MAX_SEGMENTS * TP_SIZE

# state slots (`state`): the Joule power and the held stress f / area, then one block per segment
X_P, X_STRESS = range(2)
X_SEGMENTS = 2
# a segment's block: temperature [C], martensite fraction, strain, stress (unclamped), the stress
# of the last maximum strain and its value, the stress-clamp flag (0 none, 1 clamped; the value
# and time of the first clamp, which `Multiplier.warn_clamps` warns of), then its Preisach memory
(G_T, G_XI, G_EPS, G_SIGMA, G_EPS_MAX_SIGMA, G_EPS_MAX, G_WARN, G_WARN_SIGMA,
 G_WARN_T) = range(9)
G_MEMORY = 9


def pack(params: CapstanParams, hysteresis: Hypersurface, memory_size: int) -> np.ndarray:
    """The kernel's parameters of the fold `params` on the `hysteresis` surface, its Preisach
    memories of `memory_size` floats (layout: the ``P_*`` slots)."""
    n = int(params.n_segments)
    lengths = segment_lengths(params)
    head = np.zeros(P_HEAD)
    head[P_N] = n
    head[P_AREA] = thermal.cross_section(params.wire)
    head[P_SHIFT] = params.composition_shift
    head[P_CURRENT] = 1.0 if params.wire.drive == "current" else 0.0
    head[P_MEMORY] = memory_size
    head[P_SOURCE_R] = params.source_resistance
    head[P_RISE] = params.stress_rise
    for i, (L, h, r) in enumerate(zip(lengths, segment_h(params, lengths),
                                      tension_ratios(params))):
        head[P_LENGTHS + i] = L
        head[P_SHARES + i] = L / params.length
        head[P_RATIOS + i] = r
        head[P_THERMAL + i * TP_SIZE:P_THERMAL + (i + 1) * TP_SIZE] = thermal.pack(
            _with_length(params.wire, L, h))
    return np.concatenate([head, hypersurface.packed(hysteresis)])


def state(p: np.ndarray, memory: np.ndarray) -> np.ndarray:
    """A state array for the parameters `p` (`pack`), each segment's Preisach memory a copy of
    the new `memory` (`preisach.memory`); `start_fold` sets it."""
    n, stride = int(p[P_N]), G_MEMORY + len(memory)
    x = np.zeros(X_SEGMENTS + n * stride)
    for i in range(n):
        g = block(p, x, i)
        g[G_EPS_MAX_SIGMA] = math.nan  # no maximum strain yet
        g[G_MEMORY:] = memory
    return x


def block(p: np.ndarray, x: np.ndarray, i: int) -> np.ndarray:
    """Segment `i`'s block (0 at the clamp) of the state `x`, parameters `p`: a view (`_segment`
    from Python)."""
    stride = G_MEMORY + int(p[P_MEMORY])
    return x[X_SEGMENTS + i * stride:X_SEGMENTS + (i + 1) * stride]


@jit
def _segment(p: np.ndarray, x: np.ndarray, i: int) -> np.ndarray:
    """Segment `i`'s block (0 at the clamp) of the state `x`, parameters `p`."""
    stride = G_MEMORY + int(p[P_MEMORY])
    return x[X_SEGMENTS + i * stride:X_SEGMENTS + (i + 1) * stride]


@jit
def _thermal(p: np.ndarray, i: int) -> np.ndarray:
    """Segment `i`'s thermal parameters (`thermal.pack`) of `p`."""
    return p[P_THERMAL + i * TP_SIZE:P_THERMAL + (i + 1) * TP_SIZE]


@jit
def _stress(p: np.ndarray, g: np.ndarray, i: int, f: float,
            t: float) -> tuple[float, float]:
    """`Multiplier.stresses`' stress [Pa] of segment `i` (block `g`) under the load `f` [N] at `t`
    [s], and that stress clamped to the data set's stresses, the first clamp kept in `g` (G_WARN
    1, its value and time)."""
    stress = f * p[P_RATIOS + i] / p[P_AREA]
    return stress, stress_in_range(p[P_HEAD:], stress, g, G_WARN, t)


@jit
def _eps_max(s: np.ndarray, g: np.ndarray, sigma: float) -> float:
    """F(a0, b0; `sigma`) on the packed surface `s`, evaluated once per new stress (block
    `g`)."""
    if g[G_EPS_MAX_SIGMA] != sigma:
        g[G_EPS_MAX_SIGMA] = sigma
        g[G_EPS_MAX] = surface_F(s, s[S_THI], s[S_TLO], sigma)
    return g[G_EPS_MAX]


@jit
def _seen(p: np.ndarray, s: np.ndarray, T: float, sigma: float) -> float:
    """Temperature [C] the hysteresis sees at `T` [C] under the (unclamped) stress `sigma` [Pa]:
    composition-shifted and, with the effect "hysteresis above the data's stresses" on, lowered
    by ``stress_rise`` times the stress above the data set's highest (the wire transforms that
    much hotter, §pulse-gap); saturated at the grid."""
    T_seen = T - p[P_SHIFT] - p[P_RISE] * fmax(sigma - s[S_SHI], 0.0)  # off: minus 0.0, T's bits
    return fmin(fmax(T_seen, s[S_TLO]), s[S_THI])


@jit
def source_total(p: np.ndarray, x: np.ndarray) -> float:
    """The resistance [Ohm] the supply drives under voltage drive, of the kernel's parameters
    `p` (`pack`) and state `x` (`state`): the segments' series resistance plus the source
    resistance (effect "supply resistance", §pulse-gap)."""
    return resistance_sum(p, x) + p[P_SOURCE_R]  # off: plus 0.0, the sum's bits


@jit
def resistance_sum(p: np.ndarray, x: np.ndarray) -> float:
    """`Multiplier.resistance`: the segments' series resistance [Ohm] of the kernel's
    parameters `p` (`pack`) and state `x` (`state`)."""
    acc = 0.0
    for i in range(int(p[P_N])):
        acc += resistance_k(_thermal(p, i), _segment(p, x, i)[G_XI])
    return acc


@jit
def _drive(p: np.ndarray, x: np.ndarray, i: int, u: float, total: float) -> float:
    """Segment `i`'s electrical input: the series current `u`, or its share u R_i / `total` of
    the voltage (`segment_voltages`; `total` includes the source resistance)."""
    if p[P_CURRENT] != 0.0:
        return u
    return u * (resistance_k(_thermal(p, i), _segment(p, x, i)[G_XI]) / total)


@jit
def joule_power_sum(p: np.ndarray, x: np.ndarray, u: float) -> float:
    """`Multiplier.joule_power` of the input `u` (a voltage, or a current where the
    parameters `p` say so), the state `x`."""
    total = source_total(p, x) if p[P_CURRENT] == 0.0 else 0.0
    acc = 0.0
    for i in range(int(p[P_N])):
        acc += joule_power_k(_thermal(p, i), _drive(p, x, i, u, total), _segment(p, x, i)[G_XI])
    return acc


@jit
def weighted_sum(p: np.ndarray, x: np.ndarray, weights: int, field: int) -> float:
    """Sum over the segments of their state slot `field` (of the state `x`) times the
    parameter slot `weights` + i (of the parameters `p`): `displacement`, `mean_temperature`,
    `mean_strain`."""
    acc = 0.0
    for i in range(int(p[P_N])):
        acc += _segment(p, x, i)[field] * p[weights + i]
    return acc


@jit
def start_fold(p: np.ndarray, x: np.ndarray, T_init: float, u: float, f: float,
               t: float) -> None:
    """`Multiplier.start` of the parameters `p` into the state `x`: every segment at `T_init`
    [C], all-off memory then T_init, under the load `f` [N] at `t` [s], the power that of the
    input `u`."""
    s = p[P_HEAD:]
    for i in range(int(p[P_N])):
        g = _segment(p, x, i)
        stress, sigma = _stress(p, g, i, f, t)
        g[G_T] = T_init
        eps = mem_reset(s, g[G_MEMORY:], _seen(p, s, T_init, stress), sigma)
        g[G_XI] = martensite_fraction_k(eps, _eps_max(s, g, sigma))
        g[G_EPS] = eps
        g[G_SIGMA] = stress
    x[X_P] = joule_power_sum(p, x, u)
    x[X_STRESS] = f / p[P_AREA]


@jit
def step_fold(p: np.ndarray, x: np.ndarray, u: float, T_amb: float, f: float, t: float,
              dt: float) -> None:
    """`Multiplier.step` of the parameters `p`: advance the state `x` over [`t`, `t` + `dt`] [s]
    with the input `u`, ambient `T_amb` [C] and load `f` [N] held."""
    s = p[P_HEAD:]
    total = source_total(p, x) if p[P_CURRENT] == 0.0 else 0.0
    x[X_P] = joule_power_sum(p, x, u)
    for i in range(int(p[P_N])):
        g = _segment(p, x, i)
        stress, sigma = _stress(p, g, i, f, t)
        ui = _drive(p, x, i, u, total)
        eps_max = _eps_max(s, g, sigma)
        T_new = step_k(_thermal(p, i), g[G_T], ui, T_amb, g[G_XI], 0.0, dt)
        eps = mem_step(s, g[G_MEMORY:], _seen(p, s, T_new, stress), sigma)
        g[G_XI] = martensite_fraction_k(eps, eps_max)
        g[G_EPS] = eps
        g[G_T] = T_new
        g[G_SIGMA] = stress
    x[X_STRESS] = f / p[P_AREA]


@jit
def evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """The outputs `y` (`OUTPUTS`) of the state `x` after the last step, parameters `p` (the
    inputs `u` and the time `t` play no part: no direct feedthrough); a segment beyond
    n_segments gives 0."""
    y[0] = weighted_sum(p, x, P_LENGTHS, G_EPS)
    y[1] = weighted_sum(p, x, P_SHARES, G_EPS)
    y[2] = weighted_sum(p, x, P_SHARES, G_T) + ZERO_C
    y[3] = x[X_STRESS]
    y[4] = resistance_sum(p, x)
    y[5] = x[X_P]
    n = int(p[P_N])
    for i in range(MAX_SEGMENTS):
        if i < n:
            g = _segment(p, x, i)
            y[6 + 3 * i] = g[G_T] + ZERO_C
            y[7 + 3 * i] = g[G_EPS]
            y[8 + 3 * i] = g[G_SIGMA]
        else:
            y[6 + 3 * i] = 0.0
            y[7 + 3 * i] = 0.0
            y[8 + 3 * i] = 0.0


@jit
def advance(p: np.ndarray, x: np.ndarray, u: np.ndarray, y: np.ndarray, t: float,
            dt: float) -> None:
    """Step the fold of parameters `p`, state `x`, over [`t`, `t` + `dt`] [s] with the inputs
    `u` (`INPUTS`) held (the outputs `y` play no part)."""
    step_fold(p, x, u[0], u[1] - ZERO_C, u[2], t, dt)


KERNEL = Kernel(evaluate, advance, INPUTS, OUTPUTS)
