"""FMU slaves of the sources: kernels (`musclesim.fmu.kernel`) over the jit cores of
musclesim.components.sources.signals and .forc, and of the reference profiles of
§reference-profiles (musclesim.components.sma.profiles).

Packed layouts: SignalSource's kp is `signals.pack`'s, ForcReference's `forc.pack`'s,
StrainProfile's `profiles.pack`'s, LoadingProfile's [area, then `profiles.pack`'s]; none has a
state (kx empty): each output is a function of time.
"""
from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from musclesim.components.sma import profiles
from musclesim.components.sources import forc, signals
from musclesim.fmu import Kernel, KernelSlave, PlausibleSpec, experiment, jit, no_state



@jit
def signal_evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """SignalSource's kernel: writes the output `y` = (y) at the time `t` of the parameters `p`;
    no state `x` nor inputs `u`."""
    y[0] = signals.value_core(t, p)


@jit
def forc_evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """ForcReference's kernel: writes the outputs `y` = (T_ref, run, phase) at the time `t` of
    the parameters `p`; no state `x` nor inputs `u`."""
    y[0], y[1], y[2] = forc.value_core(t, p)


@jit
def strain_evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """StrainProfile's kernel: writes the output `y` = (eps_ref) at the time `t` of the
    parameters `p`; no state `x` nor inputs `u`."""
    y[0] = profiles.value_core(p, 0, t)


@jit
def loading_evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """LoadingProfile's kernel: writes the outputs `y` = (sigma_ref, f_ref) at the time `t` of
    the parameters `p` (the area, then the profile); no state `x` nor inputs `u`."""
    sigma = profiles.value_core(p, 1, t)
    y[0] = sigma
    y[1] = sigma * p[0]


class SignalSource(KernelSlave):
    """Constant, sine, square, triangle or ramp signal (references, loads)."""

    description = "Signal source: constant, sine, square or triangle wave around an offset, or a ramp"
    kernel = Kernel(signal_evaluate, no_state, (), ("y",))

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        self.parameters_of(signals.SignalParams)
        self.output("y", "1", "Signal")

    def setup(self) -> None:
        self.p = self.core_params(signals.SignalParams)
        self.kp = signals.pack(self.p)


class ForcReference(KernelSlave):
    """Temperature reference of the FORC identification runs with run index and phase markers."""

    default_experiment = experiment(420.0, 0.005)  # sma-forc-identification, §forc-identification
    description = ("FORC experiment reference (§forc-identification): run j heats from T_low to "
                   "T_low + j T_step along a raised cosine and cools back; outputs run index and "
                   "phase")
    kernel = Kernel(forc_evaluate, no_state, (), ("T_ref", "run", "phase"))

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        self.parameters_of(forc.ForcParams)
        self.output("T_ref", "K", "Reference temperature")
        self.output("run", "1", "Run index j = 0..n-1 (peak T_low + j T_step); -1 outside the "
                    "runs", type="Integer")
        self.output("phase", "1", "+1 heating half, -1 cooling half, 0 outside the runs",
                    type="Integer")

    def setup(self) -> None:
        self.p = self.core_params(forc.ForcParams)
        self.kp = forc.pack(self.p)


AREA_127UM = math.pi * 63.5e-6 ** 2  # m2, the 127 um wire's cross-section (§sma-wire)


class _ProfileSlave(KernelSlave):
    """A reference profile of §reference-profiles (components/sma/profiles.py) as an output
    signal."""

    names: tuple[str, ...] = ()  # profile names, indexed from 1 by the `profile` parameter
    # profiles.strain_profile or profiles.loading_profile
    make: Callable[..., profiles.Profile] | None = None

    def __init__(self, lo: float, hi: float, unit: str, plausible: PlausibleSpec,
                 **kwargs: object) -> None:
        """A profile of `unit` from `lo` to `hi` by default, whose bounds plausibly take the
        values `plausible` says (`musclesim.fmu.declare`'s); `**kwargs`: pythonfmu's."""
        super().__init__(**kwargs)
        self.parameter("profile", 1.0, "1", "Profile number: " + ", ".join(
            f"{i} = {n}" for i, n in enumerate(self.names, 1)), source="§reference-profiles",
            type="Integer")
        # the profiles are functions (components/sma/profiles.py), no parameter dataclass
        self.parameter("lo", lo, unit, "Bottom of the profile's range",
                       source="§reference-profiles", plausible=plausible)
        self.parameter("hi", hi, unit, "Top of the profile's range (= lo: constant)",
                       source="§reference-profiles", plausible=plausible)
        self.parameter("duration", profiles.DURATION, "s", "Length of the run the profile is laid "
                       "out over (the study's runs of about 550 s)", source="§reference-profiles")
        self.parameter("seed", 0.0, "1", "Seed of the random peaks and troughs",
                       source="§reference-profiles", type="Integer")

    def setup(self) -> None:
        k = self.profile
        if k != int(k) or not 1 <= k <= len(self.names):
            raise ValueError(f"profile must be one of 1..{len(self.names)} "
                             f"({', '.join(self.names)}), got {k!r}")
        if not (self.lo <= self.hi and self.duration > 0 and self.seed >= 0):
            raise ValueError(f"lo <= hi, duration > 0 and seed >= 0 are needed (got lo = "
                             f"{self.lo!r}, hi = {self.hi!r}, duration = {self.duration!r}, "
                             f"seed = {self.seed!r})")
        make = type(self).make
        assert make is not None  # each profile slave names its generator
        self.fn = make(self.names[int(k) - 1], self.lo, self.hi, self.duration, int(self.seed))
        assert self.fn.kp is not None  # the shipped profiles are packed
        self.kp = self.fn.kp


class StrainProfile(_ProfileSlave):
    """Reference strain SP I-IV of §reference-profiles."""

    default_experiment = experiment(550.0, 0.0004)  # sma-position-control, §position-control
    description = ("Reference strain profile SP I-IV of §reference-profiles (contraction, within "
                   "[lo, hi])")
    names = profiles.STRAIN_PROFILES
    make = staticmethod(profiles.strain_profile)
    kernel = Kernel(strain_evaluate, no_state, (), ("eps_ref",))

    def __init__(self, **kwargs: object) -> None:
        super().__init__(0.0, profiles.EPS_MAX, "1", (0.0, 1.0), **kwargs)  # a share of length
        self.output("eps_ref", "1", "Reference strain (contraction / length)")


class LoadingProfile(_ProfileSlave):
    """Reference stress LP I-VI of §reference-profiles."""

    default_experiment = experiment(550.0, 0.0004)  # sma-position-control, §position-control
    description = "Loading (stress) profile LP I-VI of §reference-profiles, within [lo, hi] Pa"
    names = profiles.LOADING_PROFILES
    make = staticmethod(profiles.loading_profile)
    kernel = Kernel(loading_evaluate, no_state, (), ("sigma_ref", "f_ref"))

    def __init__(self, **kwargs: object) -> None:
        super().__init__(profiles.SIGMA_LO, profiles.SIGMA_HI, "Pa", "wire stress", **kwargs)
        self.parameter("area", AREA_127UM, "m2", "Wire cross-section the force reference is for "
                       "(127 um diameter)", source="§sma-wire")
        self.output("sigma_ref", "Pa", "Reference stress")
        self.output("f_ref", "N", "Reference tension sigma_ref x area")

    def setup(self) -> None:
        super().setup()
        self.kp = np.concatenate(([self.area], self.kp))
