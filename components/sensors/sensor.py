"""A scalar sensor: first-order lag, gain, bias, seeded noise and quantisation, all off by default.

The core of every sensor FMU (thermocouple, load cell, laser displacement sensor; §sma-bench,
§named-effects): the sensing element follows the measured signal with time constant tau; the reading
scales it by a gain about the sensor's origin (0 C for a thermocouple, 0 for the others), adds a
bias and Gaussian noise and is rounded to the quantisation step.

The FMUs' kernel (`evaluate`, `advance`; `musclesim.fmu.kernel`) runs these equations compiled, its
parameters packed by `pack` and its state by `start_state`, the noise generator's state among it:
`standard_normal` draws numpy's ``default_rng(seed).standard_normal()`` stream to the bit.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from musclesim.components.checks import require
from musclesim.fmu import COMPILED, declare, jit

# kernel parameters `pack` gives (kp) and the state `start_state` gives (kx)
TAU, GAIN, ORIGIN, BIAS, NOISE_STD, QUANTUM = range(6)
HELD, WEIGHT, NOISE, RNG = range(4)  # lag (reading = held + weight x signal), noise, generator
N_STATE = RNG + 8  # the generator: PCG64's 128-bit state and increment in 32-bit limbs


@dataclass(frozen=True)
class SensorParams:
    """Lag, gain, bias, noise and quantisation of a scalar sensor; the defaults = a perfect
    sensor (§sensors). Each parameter is declared here once (`declare`); what differs per sensor
    its slave overrides: `bias`, `noise_std` and `quantum` are in the signal's unit (declared
    "1" here), and the diagnosis roles (effect bounds, calibrations) are each sensor's own."""

    tau: float = declare(0.0, "s", "Time constant of the sensing element's first-order lag "
                         "(0 = none)", source="§sensors")
    gain: float = declare(1.0, "1", "Reading gain about the sensor's origin (0 C for a "
                          "thermocouple, 0 for the others; 1 = exact)", source="§sensors")
    origin: float = 0.0  # signal value the gain leaves as it is (a thermocouple's 0 C)
    # differences of the signal's unit, plausible as such (a thermocouple's bias is no temperature)
    bias: float = declare(0.0, "1", "Reading bias (0 = off)", source="§sensors",
                          plausible="difference")
    noise_std: float = declare(0.0, "1", "Standard deviation of the reading's Gaussian noise "
                               "(0 = off)", source="§sensors", plausible="difference")
    quantum: float = declare(0.0, "1", "Quantisation step of the reading (0 = off)",
                             source="§sensors", plausible="difference")
    seed: float = declare(0.0, "1", "Seed of the noise generator (>= 0)", type="Integer")

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, positive=("gain",), non_negative=("tau", "noise_std", "quantum"))
        if self.seed != int(self.seed) or self.seed < 0:
            raise ValueError(f"seed must be a non-negative whole number (got {self.seed!r})")


@jit
def lag_weights(dt: float, tau: float) -> tuple[float, float]:
    """(a, b) of the exact first-order lag of time constant `tau` over `dt` for an input linear
    between two samples:
    y1 = a y0 + (1 - a - b) u0 + b u1, with a = exp(-dt/tau), b = 1 - tau (1 - a) / dt.

    Continuous in tau: at tau = 0 the reading is the signal itself (a = 0, b = 1), and a lag
    much shorter than the step is a small delay, not a whole step of it (as a held input gives).

    >>> lag_weights(0.02, 0.0)
    (0.0, 1.0)
    >>> a, b = lag_weights(0.02, 1e-9); round(a, 12), round(b, 6)
    (0.0, 1.0)
    """
    if tau <= 0:
        return 0.0, 1.0
    a = math.exp(-dt / tau)
    return a, 1.0 - tau * (-math.expm1(-dt / tau)) / dt


def noise_sample(p: SensorParams, rng: np.random.Generator) -> float:
    """One noise sample of the reading of the sensor `p` from `rng` (0 when the noise is off; the
    generator is not used then)."""
    return p.noise_std * rng.standard_normal() if p.noise_std > 0 else 0.0


def reading(x: float, p: SensorParams, noise: float = 0.0) -> float:
    """Reading of the sensor `p` of the (lagged) signal `x`: gain about the origin, bias, the
    `noise` sample,
    quantisation.

    Examples
    --------
    >>> reading(300.26, SensorParams(bias=-1.0, quantum=0.25))
    299.25
    >>> round(reading(373.15, SensorParams(gain=1.01, origin=273.15)), 6)  # 100 C reads 101 C
    374.15
    """
    return read(x, p.gain, p.origin, p.bias, p.quantum, noise)


@jit
def read(x: float, gain: float, origin: float, bias: float, quantum: float,
         noise: float) -> float:
    """`reading` of `x` with the parameters as numbers: `gain` about `origin`, `bias`, the
    `noise` sample, rounded to `quantum`."""
    if gain != 1.0:
        x = origin + gain * (x - origin)
    y = x + bias + noise
    if quantum > 0:
        y = quantum * round(y / quantum)
    return y


def make_rng(p: SensorParams) -> np.random.Generator:
    """The random generator of the sensor `p` (its state is part of the FMU state)."""
    return np.random.default_rng(int(p.seed))


# ---- the kernel -------------------------------------------------------------------------------
def pack(p: SensorParams) -> np.ndarray:
    """The kernel's parameters kp of `p`: [tau, gain, origin, bias, noise_std, quantum] (indices
    TAU, GAIN, ORIGIN, BIAS, NOISE_STD, QUANTUM)."""
    return np.array([p.tau, p.gain, p.origin, p.bias, p.noise_std, p.quantum], dtype=np.float64)


def start_state(p: SensorParams) -> np.ndarray:
    """The kernel's state kx of `p` at the start: [held, weight, noise, generator (8)] (indices
    HELD, WEIGHT, NOISE, RNG): no lag yet (held 0, weight 1), the generator `make_rng` gives and
    the noise of the first step drawn from it, as `noise_sample` draws it."""
    x = np.zeros(N_STATE)
    x[WEIGHT] = 1.0
    pcg = make_rng(p).bit_generator.state["state"]
    for k, value in enumerate((pcg["state"], pcg["inc"])):
        for j in range(4):
            x[RNG + 4 * k + j] = float((value >> (96 - 32 * j)) & 0xFFFFFFFF)
    x[NOISE] = p.noise_std * standard_normal(x, RNG) if p.noise_std > 0 else 0.0
    return x


@jit
def element(x: np.ndarray, u: float) -> float:
    """The sensing element's value now: what the past steps left in the state `x` plus the
    present signal `u`'s share (`lag_weights`, the signal taken linear over a step)."""
    return u if x[WEIGHT] == 1.0 and x[HELD] == 0.0 else x[HELD] + x[WEIGHT] * u


@jit
def evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """The kernel's output: `y` = [reading] of the signal `u` = [signal] in the state `x`, of the
    parameters `p`; the time `t` unused."""
    y[0] = read(element(x, u[0]), p[GAIN], p[ORIGIN], p[BIAS], p[QUANTUM], x[NOISE])


@jit
def advance(p: np.ndarray, x: np.ndarray, u: np.ndarray, y: np.ndarray, t: float,
            dt: float) -> None:
    """The lag of the state `x` (in place) over [`t`, `t` + `dt`] from the signal `u` =
    [signal], and the next step's noise sample (one per communication step), of the parameters
    `p`; the outputs `y` unused."""
    y0, u0 = element(x, u[0]), u[0]
    a, b = lag_weights(dt, p[TAU])
    x[HELD], x[WEIGHT] = a * y0 + (1.0 - a - b) * u0, b
    x[NOISE] = p[NOISE_STD] * standard_normal(x, RNG) if p[NOISE_STD] > 0 else 0.0


# ---- numpy's standard_normal on a generator state in an array -----------------------------------
if COMPILED:  # numpy's PCG64 and ziggurat, ported: their tables are numba's copy of numpy's
    from numba.np.random import _constants as _zig

    _KI = np.asarray(_zig.ki_double, dtype=np.int64)
    _WI = np.asarray(_zig.wi_double, dtype=np.float64)
    _FI = np.asarray(_zig.fi_double, dtype=np.float64)
    _R, _INV_R = float(_zig.ziggurat_nor_r), float(_zig.ziggurat_nor_inv_r)
    _M_HI, _M_LO = np.uint64(0x2360ED051FC65DA4), np.uint64(0x4385DF649FCCF645)  # PCG64's
    _U32, _S32, _S58 = np.uint64(0xFFFFFFFF), np.uint64(32), np.uint64(58)
    _S8, _S9, _S11, _ONE, _M52 = (np.uint64(8), np.uint64(9), np.uint64(11), np.uint64(1),
                                  np.uint64(0x000FFFFFFFFFFFFF))

    @jit
    def _limbs(x: np.ndarray, i: int) -> tuple[np.uint64, np.uint64]:
        """The 128-bit number in 32-bit limbs x[i:i+4] as (high, low) 64-bit words."""
        return ((np.uint64(x[i]) << _S32) | np.uint64(x[i + 1]),
                (np.uint64(x[i + 2]) << _S32) | np.uint64(x[i + 3]))

    @jit
    def _next64(x: np.ndarray, i: int) -> np.uint64:
        """PCG64's next output (XSL-RR of the state after a step), the state x[i:i+8] advanced."""
        s_hi, s_lo = _limbs(x, i)
        inc_hi, inc_lo = _limbs(x, i + 4)
        a0, a1, b0, b1 = s_lo & _U32, s_lo >> _S32, _M_LO & _U32, _M_LO >> _S32
        p00, p01, p10 = a0 * b0, a0 * b1, a1 * b0
        mid = (p00 >> _S32) + (p01 & _U32) + (p10 & _U32)
        lo = (mid << _S32) | (p00 & _U32)  # s_lo M_LO: its low and high words
        hi = a1 * b1 + (p01 >> _S32) + (p10 >> _S32) + (mid >> _S32)
        hi = hi + s_hi * _M_LO + s_lo * _M_HI
        lo = lo + inc_lo
        hi = hi + inc_hi + (_ONE if lo < inc_lo else np.uint64(0))
        x[i], x[i + 1] = float(hi >> _S32), float(hi & _U32)
        x[i + 2], x[i + 3] = float(lo >> _S32), float(lo & _U32)
        v, rot = hi ^ lo, hi >> _S58
        return (v >> rot) | (v << ((np.uint64(64) - rot) & np.uint64(63)))

    @jit
    def _next_double(x: np.ndarray, i: int) -> float:
        return np.int64(_next64(x, i) >> _S11) * (1.0 / 9007199254740992.0)

    @jit
    def standard_normal(x: np.ndarray, i: int) -> float:
        """numpy's ``Generator.standard_normal()`` of the PCG64 generator whose state is in
        `x` from `i`, x[i:i+8] (state, increment: 32-bit limbs, high first), the state advanced."""
        while True:
            r = _next64(x, i)
            idx = np.int64(r & np.uint64(0xFF))
            rabs = np.int64((r >> _S9) & _M52)
            z = rabs * _WI[idx]
            if (r >> _S8) & _ONE:
                z = -z
            if rabs < _KI[idx]:
                return z
            if idx == 0:
                while True:
                    xx = -_INV_R * math.log1p(-_next_double(x, i))
                    yy = -math.log1p(-_next_double(x, i))
                    if yy + yy > xx * xx:
                        return -(_R + xx) if (rabs >> 8) & 1 else _R + xx
            elif (_FI[idx - 1] - _FI[idx]) * _next_double(x, i) + _FI[idx] < math.exp(-0.5 * z * z):
                return z
else:  # numpy's own generator, its state passed through the array
    _PCG = np.random.PCG64()
    _GEN = np.random.Generator(_PCG)

    def standard_normal(x: np.ndarray, i: int) -> float:
        """numpy's ``Generator.standard_normal()`` of the PCG64 generator whose state is in
        `x` from `i`, x[i:i+8] (state, increment: 32-bit limbs, high first), the state advanced."""
        words = [int(v) for v in x[i:i + 8]]
        state, inc = (sum(w << (96 - 32 * j) for j, w in enumerate(words[k:k + 4]))
                      for k in (0, 4))
        _PCG.state = {"bit_generator": "PCG64", "state": {"state": state, "inc": inc},
                      "has_uint32": 0, "uinteger": 0}
        z = float(_GEN.standard_normal())
        state = _PCG.state["state"]["state"]
        for j in range(4):
            x[i + j] = float((state >> (96 - 32 * j)) & 0xFFFFFFFF)
        return z
