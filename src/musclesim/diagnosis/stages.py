"""What the diagnosis's stages hand each other (`musclesim.diagnosis.pipeline`): frozen values in
place of tuples, as FMPy passes `Recorder` and `Input` objects between its steps.

`Nominal` (an isolation unit's nominal run), `Calibration` (a unit's calibration),
`Isolation` (a unit calibrated on its own) and `FitUnit` (where the candidates are fitted).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from musclesim.cosim import ParamRef, Signal
    from musclesim.diagnosis.fitting import FitResult, Free
    from musclesim.diagnosis.problem import Unit

__all__ = ["Nominal", "Calibration", "Isolation", "FitUnit"]

Residuals = dict[str, list[np.ndarray]]  # {observed column: [array per run]}


@dataclass(frozen=True)
class Nominal:
    """An isolation `unit`'s nominal run: its `residuals`, and whether it `deviates`."""

    unit: Unit
    residuals: Residuals
    deviates: bool


@dataclass(frozen=True)
class Calibration:
    """A unit's calibration: its `Free` parameters and their fitted `values`, the `residuals`
    there, the Jacobian `jac` (box coordinates, None: nothing calibrated), the report's `table`
    of values, the `FitResult` `fit` (None: nothing calibrated), the sensor `latency` held and
    the held-out gap of the nominal values (`nominal_gap`)."""

    free: list[Free]
    values: dict[ParamRef, float]
    residuals: Residuals
    jac: np.ndarray | None
    table: dict[str, dict[str, Any]]
    fit: FitResult | None
    latency: dict[Signal, int]
    nominal_gap: float


@dataclass(frozen=True)
class Isolation:
    """An isolation `unit` with its own `calibration`: its held-out `gap` and noise `floor`,
    whether it `deviates`, the nominal values' gap (`nominal_gap`)."""

    unit: Unit
    calibration: Calibration
    gap: float
    floor: float
    deviates: bool
    nominal_gap: float

    def section(self) -> dict[str, Any]:
        """The report's entry of this unit (``units``)."""
        return {"instances": list(self.unit.instances), "observed": list(self.unit.observed),
                "heldout_gap_nominal": self.nominal_gap, "heldout_gap": self.gap,
                "noise_floor": self.floor, "deviates": self.deviates}


@dataclass(frozen=True)
class FitUnit:
    """Where the candidates are fitted: the `unit`, its `calibration` and the `suspects` (the
    instances whose components' effects are the candidates)."""

    unit: Unit
    calibration: Calibration
    suspects: frozenset[str]
