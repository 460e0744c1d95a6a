"""FMU slaves of the SMA wire and of its inverse: thin adapters over the wire's core (`smawire`,
its submodels, the Preisach and drift cores) and the inverse core."""
from __future__ import annotations

import math

import numpy as np

from musclesim.components.sma import (datasets, inversekernel, ports, smawire, surface, thermal,
                                      wirekernel)
from musclesim.components.sma.inverse import InverseBases
from musclesim.components.sma.ports import LOAD_150G
from musclesim.components.sma.smawire import HYSTERESIS, ZERO_C
from musclesim.components.sma.surface import Hypersurface, clamp
from musclesim.fmu import KernelSlave, experiment

__all__ = ["SmaWire", "PreisachInverse", "LOAD_150G", "HYSTERESIS", "ZERO_C"]

# id(surface) -> (surface, its InverseBases, the inverse kernel's parameters); the surface is
# held, so ids stay unique
_BASES: dict[int, tuple[Hypersurface, InverseBases, np.ndarray]] = {}


class SmaWire(KernelSlave):
    """SMA wire: Joule heating and convection (§thermal-model) drive the modified Preisach model
    (§preisach).

    A thin adapter over `smawire.SmaWireCore`'s compiled kernel (`wirekernel`): per communication step, with the inputs held from
    its start, the temperature advances by the lumped thermal model (resistance from the
    martensite fraction at the start of the step), then the hysteresis model takes the new
    temperature and the stress flange.f / area; its strain gives the martensite fraction for the
    next step. No output depends directly on an input (stress and power are those of the step just
    taken), so the wire closes loops with controllers and loads without an algebraic loop.
    Temperatures outside the data set's grid (30..130 C) saturate the hysteresis
    (§thermal-model); stresses outside its stresses are clamped with one warning in the FMU log.
    Effects (latent heat, cold ends, h(T), drift, stress ignored and partly restored) are off by
    default. With cold ends (`end_cooling` > 0, `ends`) the temperature T is the core's, and each
    end zone has its own hysteresis memory at its own temperature; strain, resistance and power
    are the wire's, averaged over its length. Every parameter is declared once, in
    `thermal.ThermalParams` and `smawire.SmaWireParams`. Equations: §thermal-model and §preisach
    (docs/model/).
    """

    kernel = wirekernel.KERNEL
    default_experiment = experiment(30.0, 0.0004)  # the SMA bench at 2.5 kHz, §sma-bench
    description = ("SMA wire: lumped thermal model with phase-dependent resistance and modified "
                   "Preisach hysteresis under stress (§thermal-model, §preisach)")

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        # geometry, material, convection and the thermal effects: declared in the thermal core;
        # the rest in the wire's core
        self.parameters_of(thermal.ThermalParams)
        self.parameters_of(smawire.SmaWireParams)
        ports.declare_ports(self, "Tensile load on the wire, positive pulling (start: a 150 g "
                            "weight)", {
                                "T": "Wire temperature",
                                "strain": "Strain: contraction / length, positive = contraction "
                                          "(§sma-wire)",
                                "flange.s": "Contraction strain x length; positive = the wire "
                                            "shortens, pulling its load toward the fixed clamp",
                                "stress": "Tensile stress flange.f / cross-section over the last "
                                          "step (§sma-wire)",
                                "R": "Electrical resistance R(xi) (§thermal-model)",
                                "P": "Joule heating power over the last step (input held, "
                                     "resistance at its start)",
                                "xi": "Martensite fraction, 1 - hysteresis strain / its maximum"})

    def setup(self) -> None:
        """Check the parameters and build the wire's core and its kernel's arrays."""
        params = self.core_params(smawire.SmaWireParams)
        self.core = smawire.SmaWireCore(params, thermal.params_of(self, params.drive),
                                        datasets.shipped(self.resources))
        self.kp, self.kx = self.core.kp, self.core.kx
        self._warned: set[str] = set()
        self._start()

    def initialize(self) -> None:
        """The initial state, from the inputs (ambient, load) as they are now."""
        self._start()

    def _start(self) -> None:
        """Initial state: a new (or drift_cycles_start old) wire heated to T_init."""
        sigma = self._stress(self.time)
        self.core.start(self.u, self.T_amb - ZERO_C, self.flange_f, sigma, self.time)

    def advance(self, t: float, dt: float) -> None:
        """The kernel's step over [`t`, `t` + `dt`] [s] with the inputs held, its inputs checked
        first and its first stress clamp logged after (the kernel keeps it in its state)."""
        ports.check_inputs(self.u, self.T_amb, self.flange_f, t)
        super().advance(t, dt)
        self._log_clamp()
        if self.kx[wirekernel.X_ERROR]:
            smawire.raise_error(self.kx)

    def restore_kernel(self, x: np.ndarray, u: np.ndarray, y: np.ndarray, time: float,
                       dirty: bool) -> None:
        """`KernelSlave.restore_kernel` (the state `x`, inputs `u`, outputs `y`, clock `time`
        [s] and `dirty` a master reached running the kernel itself), then the first stress clamp
        the kernel kept in its state logged as `advance` logs it."""
        super().restore_kernel(x, u, y, time, dirty)
        self._log_clamp()

    def _stress(self, t: float) -> float:
        """Stress [Pa] for the hysteresis at the start: the kernel's (`wirekernel.stress`),
        clamped to the data set's stresses, the clamp logged once."""
        sigma = wirekernel.stress(self.kp, self.kx, self.flange_f, t)
        self._log_clamp()
        return sigma

    def _log_clamp(self) -> None:
        """Log the first clamp of the stress the kernel kept in its state (its value and time) as
        `clamp` words it, once."""
        kx = self.kx
        if kx[wirekernel.X_WARN] == 1.0 and "stress" not in self._warned:
            s = self.core.surface
            self.logged(clamp, self._warned, "stress", float(kx[wirekernel.X_WARN_SIGMA]),
                        s.s_lo, s.s_hi, "Pa", float(kx[wirekernel.X_WARN_T]))


class PreisachInverse(KernelSlave):
    """Inverse of the modified Preisach model (§preisach-inverse): reference strain and stress in,
    the temperature reference that makes the wire produce that strain out (feed-forward).

    A thin adapter over `inverse.PreisachInverse`'s compiled kernel (`inversekernel`). T_ref is direct feedthrough: at every
    communication point it is the core's `peek` at the present inputs (memory untouched); each
    step commits that sample with the core's `step`, so the memory sees every sample once, exactly
    as the core stepped by hand (clear at initialization, then one step per communication step =
    reset, step, step, ...). ``sigma_surface`` = 0: stress-aware inverse over the hypersurface;
    > 0: the single constant-stress surface at that stress for every stress ("stress ignored").
    Equations: §preisach-inverse.
    """

    kernel = inversekernel.KERNEL
    default_experiment = experiment(550.0, 0.0004)  # sma-position-control, §position-control
    description = ("Feed-forward inverse of the modified Preisach model: reference strain and "
                   "stress in, temperature reference out (§position-control)")

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        self.parameter("hysteresis", 0.0, "1", HYSTERESIS + "; set it to the data set the "
                       "wire is modelled with", source="§preisach", type="Integer")
        self.parameter("sigma_surface", 0.0, "Pa",
                       "0 = stress-aware inverse over the hypersurface; > 0 = the single surface "
                       "at this stress for every stress, stress ignored, the study's comparison "
                       "inverse (within the data set's stresses: 105-145 MPa for data sets 1 and "
                       "2, 60-200 MPa for 0)", source="§position-control",
                       plausible="wire stress")
        self.input("eps_ref", 0.0, "1", "Reference strain: contraction / length, positive = "
                   "contraction, within [0, maximum strain of the data set] (start: a cold "
                   "wire)")
        self.input("sigma_ref", LOAD_150G / thermal.cross_section(thermal.ThermalParams()), "Pa",
                   "Reference stress (start: the 150 g weight on the 127 um wire, 116 MPa)",
                   plausible="wire stress")
        self.output("T_ref", "K", "Temperature reference for the wire's temperature controller",
                    depends=["eps_ref", "sigma_ref"])

    def setup(self) -> None:
        """Load the data set's surface, the inverse's bases and the kernel's parameters (once per
        process), then start."""
        self.surface = datasets.surface(self.hysteresis, self.sigma_surface,
                                        datasets.shipped(self.resources))
        key = id(self.surface)
        if key not in _BASES:  # ~0.1-0.3 s per data set: once per process
            bases = InverseBases(self.surface)
            _BASES[key] = (self.surface, bases, inversekernel.pack(self.surface, bases))
        _, self.bases, self.kp = _BASES[key]
        self._start()

    def initialize(self) -> None:
        """Clear the memory at the reference stress, now that the inputs are known."""
        self._start()

    def _start(self) -> None:
        """A new memory (and its one-time warnings), cleared at the reference stress."""
        self.kx = inversekernel.new_state()
        self.core = inversekernel.InverseState(self.bases, self.kx)
        self._warned: set[str] = set()
        self._checked(self.time)
        inversekernel.clear(self.kp, self.kx, self.sigma_ref, self.time)
        self._log_clamps()

    def evaluate(self) -> None:
        """T_ref: the kernel's `peek` at the present inputs, its memory untouched."""
        self._checked(self.time)
        super().evaluate()
        self._log_clamps()

    def advance(self, t: float, dt: float) -> None:
        """Commit the inputs at `t` [s] with the kernel's `step` (the step `dt` [s] plays no
        part: the inverse has no dynamics)."""
        self._checked(t)
        super().advance(t, dt)
        self._log_clamps()

    def restore_kernel(self, x: np.ndarray, u: np.ndarray, y: np.ndarray, time: float,
                       dirty: bool) -> None:
        """`KernelSlave.restore_kernel` (the state `x`, inputs `u`, outputs `y`, clock `time`
        [s] and `dirty` a master reached running the kernel itself), then the first clamps the
        kernel kept in its state logged as `advance` logs them."""
        super().restore_kernel(x, u, y, time, dirty)
        self._log_clamps()

    def _log_clamps(self) -> None:
        """Log the kernel's first clamp of the reference strain and of the stress (kept in its
        state), as the core's `clamp` words them, each once."""
        x, k = self.kx, inversekernel
        if x[k.X_WARN_EPS] == 1.0 and "reference strain" not in self._warned:
            self.logged(clamp, self._warned, "reference strain", float(x[k.X_WARN_EPS_VALUE]),
                        0.0, float(self.kp[k.I_EPS_HI]), "", float(x[k.X_WARN_EPS_T]))
        if x[k.X_WARN_SIGMA] == 1.0 and "stress" not in self._warned:
            s = self.kp[int(self.kp[k.I_SURFACE]):]
            self.logged(clamp, self._warned, "stress", float(x[k.X_WARN_SIGMA_VALUE]),
                        float(s[surface.S_MSLO]), float(s[surface.S_MSHI]), "Pa",
                        float(x[k.X_WARN_SIGMA_T]))

    def _checked(self, t: float) -> None:
        for name, value in (("eps_ref", self.eps_ref), ("sigma_ref", self.sigma_ref)):
            if not math.isfinite(value):
                raise ValueError(f"input {name} is {value!r} at t = {t:g} s")
