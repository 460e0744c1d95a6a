"""The SmaWire FMU's physics core: its parameters beyond the thermal core's, each declared once
(`SmaWireParams`), and `SmaWireCore`, the lumped wire composed of submodels (thermal: lumped, with
latent heat; ends: none, cold — `submodels`), the modified Preisach hysteresis and the training
drift.

Per step, with the inputs held from its start: the temperature advances by the thermal submodel
(resistance from the martensite fraction at the start of the step), then the hysteresis takes the
new temperature and the stress; its strain gives the martensite fraction for the next step. With
cold ends the temperature is the core's, and each end zone has its own hysteresis memory at its
own temperature; strain, resistance and power are the wire's, averaged over its length.
Temperatures in degrees C, stresses in Pa. Equations: §thermal-model and §preisach (docs/model/).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from musclesim.components.sma import datasets, drift, preisach, submodels, thermal, wirekernel
from musclesim.fmu import Calibration, declare

__all__ = ["HYSTERESIS", "SmaWireParams", "SmaWireCore"]

HYSTERESIS = ("Hysteresis data set: 0 = reference wire (1 C grid, 60-200 MPa); k >= 1 = FORC "
              "data set k of sma/data/forc-sets.toml shipped in the FMU")
ZERO_C = wirekernel.ZERO_C  # K; the FMU speaks K, the cores C
_NO_DRIFT = drift.DriftParams()  # the drift's defaults: off, and its pace (§drift)


@dataclass(frozen=True)
class SmaWireParams:
    """The SmaWire's parameters beyond the wire's geometry, material, convection and thermal
    effects (`thermal.ThermalParams`): its initial state, electrical input, hysteresis data set,
    stress handling, cold ends, training drift and the hysteresis's calibrations, each declared
    once here (`declare`) in the FMU's order."""

    T_init: float = declare(293.15, "K", "Initial wire temperature (assumption: room "
                            "temperature); the wire starts fully martensitic, as below 30 C, and "
                            "heated to it", source="§thermal-model, §preisach",
                            calibrate=Calibration(-5.0, 5.0, False, "the wire's temperature when "
                                                  "the record starts"))
    drive_current: float = declare(0.0, "1", "Electrical input u: 0 = voltage [V] (default; the "
                                   "study heated with 0-2.5 V), 1 = current [A] (the data sheets' "
                                   "ratings, such as 0.3 A)", source="§thermal-model",
                                   type="Boolean")
    hysteresis: float = declare(0.0, "1", HYSTERESIS, source="§preisach", type="Integer")
    sigma_surface: float = declare(0.0, "Pa", "Stress ignored, 0 = off: > 0 uses the single "
                                   "constant-stress surface at this stress (within the data set's "
                                   "stresses) for every stress, as the study's comparison "
                                   "controller did", source="§position-control",
                                   plausible="wire stress")
    stress_blend: float = declare(0.0, "1", "Effect, 0 = off: with sigma_surface > 0, how much "
                                  "the hysteresis follows the stress: it sees sigma_surface + "
                                  "stress_blend (stress - sigma_surface) on the stress-aware data "
                                  "set", source="§position-control, §named-effects",
                                  effect=(0.0, 1.0))
    end_cooling: float = declare(0.0, "1", "Effect, 0 = off: cold ends, the share of the core's "
                                 "excess temperature lost at the clamps, G_c / (G_c + G_f) "
                                 "(insulating clamps 0, metal clamps about 0.9)",
                                 source="§named-effects, §thermal-model", effect=(0.0, 1.0))
    conductivity: float = declare(18.0, "W/(m.K)", "Thermal conductivity of NiTi (literature); "
                                  "used only by the cold ends, whose fin length it sets",
                                  source="§sma-material")
    drift_amplitude: float = declare(_NO_DRIFT.amplitude_change, "1", "Effect, 0 = off: training/"
                                     "fatigue drift, the settled relative change of the strain "
                                     "amplitude (the study gives no magnitude)", source="§drift",
                                     effect=(-0.2, 0.2))
    drift_shift: float = declare(_NO_DRIFT.shift, "K", "Effect, 0 = off: training/fatigue drift, "
                                 "the settled shift of the transformation temperatures (the study "
                                 "gives no magnitude)", source="§drift", effect=(-10.0, 10.0),
                                 plausible="difference")
    drift_settle_cycles: float = declare(_NO_DRIFT.cycles_to_settle, "1", "Training/fatigue "
                                         "drift: e-folding number of cycles (95 % of the drift "
                                         "after the study's 13 tests of 20 cycles, read as 13 "
                                         "tests in all)", source="§drift")
    drift_cycles_start: float = declare(0.0, "1", "Training/fatigue drift: transformation cycles "
                                        "done before the run (a new wire 0, a later test of the "
                                        "study's protocol 20 per earlier test)", source="§drift")
    hysteresis_shift: float = declare(0.0, "K", "Static shift of the transformation temperatures: "
                                      "the hysteresis sees T - shift (composition, heat "
                                      "treatment, a core hotter than the temperature measured)",
                                      plausible="difference",
                                      source="§preisach, §named-effects, §sma-material",
                                      calibrate=Calibration(-8.0, 8.0, False, "transformation "
                                                            "temperatures shift with composition "
                                                            "and training"))
    strain_scale: float = declare(1.0, "1", "Factor on the transformation strain (the wire's "
                                  "recoverable strain, its gauge length)",
                                  source="§forc-identification, §sma-material",
                                  calibrate=Calibration(0.85, 1.15, True, "the recoverable strain "
                                                        "differs from wire to wire"))

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        if self.drive_current not in (0.0, 1.0):
            raise ValueError(f"drive_current must be 0 (voltage) or 1 (current), "
                             f"got {self.drive_current!r}")
        if not self.T_init > 0:
            raise ValueError(f"T_init must be positive in K (got {self.T_init!r})")
        if not 0 <= self.stress_blend <= 1:
            raise ValueError(f"stress_blend must be within [0, 1] (got {self.stress_blend!r})")
        if not self.strain_scale > 0 or not math.isfinite(self.hysteresis_shift):
            raise ValueError(f"strain_scale must be positive and hysteresis_shift finite (got "
                             f"{self.strain_scale!r}, {self.hysteresis_shift!r})")
        if not self.drift_cycles_start >= 0:
            raise ValueError(f"drift_cycles_start must be non-negative "
                             f"(got {self.drift_cycles_start!r})")

    @property
    def drive(self) -> str:
        """The thermal core's electrical input, "current" or "voltage" (`drive_current`)."""
        return "current" if self.drive_current == 1 else "voltage"

    def drift_params(self) -> drift.DriftParams:
        """The drift core's parameters (`drift.DriftParams`) of the FMU's drift parameters."""
        return drift.DriftParams(amplitude_change=self.drift_amplitude, shift=self.drift_shift,
                                 cycles_to_settle=self.drift_settle_cycles)


class SmaWireCore:
    """The SmaWire's physics: `params` (`SmaWireParams`) and `wire` (`thermal.ThermalParams`) on
    the hysteresis data sets below `root` (`datasets.shipped`), checked here (ValueError naming
    the parameter). `start` sets the initial state, `step` advances it; the stress the hysteresis
    takes (`stress_seen`, clamped by the caller to `surface`'s stresses) is an argument of both.

    The submodels it composes (`thermal`, `ends`) are written once as the compiled kernel
    `wirekernel`: the state lives in its arrays ``kp`` (parameters) and ``kx`` (state), which the
    SmaWire FMU steps; the attributes below read them.
    """

    def __init__(self, params: SmaWireParams, wire: thermal.ThermalParams, root: Path) -> None:
        wire.check()
        self.params, self.p = params, wire
        self.dp = params.drift_params()
        self.dp.check()
        # stress_blend > 0 puts back part of the stress dependence that sigma_surface removed
        self.blend = params.sigma_surface > 0 and params.stress_blend > 0
        self.surface = datasets.surface(params.hysteresis, params.sigma_surface, root)
        if self.blend:
            self.surface = datasets.surface(params.hysteresis, 0.0, root)
        self.area = thermal.cross_section(wire)
        self.ends = submodels.ends_submodel(params.end_cooling, wire.length, wire.diameter,
                                            params.conductivity, wire.h)
        self.thermal = submodels.thermal_submodel(wire)
        memory = preisach.memory()
        self.kp = wirekernel.pack(params, wire, self.surface, self.ends.zones, len(memory))
        self.kx = wirekernel.state(self.kp, memory)

    @property
    def T_C(self) -> float:
        """Core temperature [C]."""
        return float(self.kx[wirekernel.X_T])

    @property
    def cycles(self) -> float:
        """Transformation cycles of the drift."""
        return float(self.kx[wirekernel.X_CYCLES])

    @property
    def xi(self) -> float:
        """The wire's martensite fraction."""
        return float(self.kx[wirekernel.X_XI])

    @property
    def xi_core(self) -> float:
        """The core's martensite fraction."""
        return float(self.kx[wirekernel.X_XI_CORE])

    @property
    def eps(self) -> float:
        """The wire's strain."""
        return float(self.kx[wirekernel.X_EPS])

    @property
    def stress_held(self) -> float:
        """Stress f / area [Pa] over the last step."""
        return float(self.kx[wirekernel.X_STRESS])

    @property
    def P_held(self) -> float:
        """Joule power [W] over the last step."""
        return float(self.kx[wirekernel.X_P])

    def stress_seen(self, f: float) -> float:
        """Stress [Pa] the hysteresis takes under the tensile load `f` [N] before clamping:
        f / area, or with `stress_blend` only that share of its departure from `sigma_surface`."""
        sigma = f / self.area
        if self.blend:
            p = self.params
            sigma = p.sigma_surface + p.stress_blend * (sigma - p.sigma_surface)
        return sigma

    def start(self, u: float, T_amb: float, f: float, sigma: float, t: float) -> None:
        """Initial state at time `t` [s]: a new (or `drift_cycles_start` old) wire heated to
        `T_init`, under the input `u`, ambient `T_amb` [C], load `f` [N] and hysteresis stress
        `sigma` [Pa]."""
        wirekernel.start(self.kp, self.kx, u, T_amb, f, sigma)

    def step(self, u: float, T_amb: float, f: float, sigma: float, t: float, dt: float) -> None:
        """Advance over [`t`, `t` + `dt`] [s] with the input `u`, ambient `T_amb` [C], load `f`
        [N] and hysteresis stress `sigma` [Pa] held."""
        wirekernel.step(self.kp, self.kx, u, T_amb, f, sigma, dt)
        raise_error(self.kx)

    def resistance(self) -> float:
        """The wire's electrical resistance R(xi) [Ohm] now (§thermal-model)."""
        return thermal.resistance(self.xi, self.p)


def raise_error(kx: np.ndarray) -> None:
    """Raise the error the kernel's state `kx` records (the latent heat's root search failed, as
    scipy's `brentq` raises), clearing it."""
    code = kx[wirekernel.X_ERROR]
    if code:
        kx[wirekernel.X_ERROR] = 0.0
        if code == 1:
            raise ValueError("f(a) and f(b) must have different signs")
        raise RuntimeError("the latent heat's root search did not converge in 100 iterations")
