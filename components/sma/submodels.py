"""The SMA wire's submodels, one class per variant behind one small interface (as PyBaMM composes a
model): thermal — `Lumped`, `LumpedLatent` (with latent heat); ends — `NoEnds`, `ColdEnds`. The
SmaWire's core (`smawire`) composes one of each from its parameters, the capstan multiplier's
segments (`musclesim.components.multiplier.capstan`) are `Lumped` with `NoEnds`.

A thermal submodel advances the lumped temperature over one step (`thermal.step`, or
`thermal.step_coupled` with latent heat). An ends submodel owns the hysteresis memories of the
cold end zones (`ends.zones`) and says how the wire's strain and the core's heating combine from the
core's and the zones'. Equations: §thermal-model, §named-effects (docs/model/sma-thermal.md).
"""
from __future__ import annotations

from collections.abc import Callable, Sequence

from musclesim.components.sma import ends, thermal
from musclesim.components.sma.preisach import PreisachModel
from musclesim.components.sma.surface import Hypersurface

__all__ = ["Lumped", "LumpedLatent", "NoEnds", "ColdEnds", "thermal_submodel", "ends_submodel"]


class Lumped:
    """Thermal submodel: the lumped balance without latent heat (`thermal.step`)."""

    def step(self, T: float, inputs: thermal.ThermalInputs, dt: float, p: thermal.ThermalParams,
             xi_at: Callable[[float], float] | None = None) -> float:
        """Wire temperature [C] after `dt` [s] from `T` [C] with `inputs` held, parameters `p`;
        `xi_at` (the martensite fraction the hysteresis would reach at a temperature) is not
        needed without latent heat."""
        return thermal.step(T, inputs, dt, p)


class LumpedLatent:
    """Thermal submodel: the lumped balance with latent heat, coupled implicitly to the hysteresis
    (`thermal.step_coupled`)."""

    def step(self, T: float, inputs: thermal.ThermalInputs, dt: float, p: thermal.ThermalParams,
             xi_at: Callable[[float], float] | None = None) -> float:
        """Wire temperature [C] after `dt` [s] from `T` [C] with `inputs` held, parameters `p`,
        the latent heat following `xi_at` (the martensite fraction the hysteresis would reach at
        a temperature, its memory untouched)."""
        if xi_at is None:
            raise ValueError("the latent heat needs the hysteresis's xi_at")
        return thermal.step_coupled(T, inputs, dt, p, xi_at)[0]


def thermal_submodel(p: thermal.ThermalParams) -> Lumped | LumpedLatent:
    """The thermal submodel of parameters `p`: `LumpedLatent` where the latent heat is on."""
    return Lumped() if p.latent_heat == 0 else LumpedLatent()


# strain_of(memory, temperature [C]): steps (or resets) a hysteresis memory at a zone's temperature
StrainOf = Callable[[PreisachModel, float], float]


class NoEnds:
    """Ends submodel: insulating clamps, a uniform wire (the nominal model)."""

    zones: Sequence[tuple[float, float]] = ()

    def reset(self, surface: Hypersurface) -> None:
        """New memories on `surface` for the end zones: none here."""

    def strain(self, eps_core: float, T_core: float, T_amb: float, strain_of: StrainOf) -> float:
        """The wire's strain: the core's `eps_core` (`T_core`, `T_amb` [C] and `strain_of` do not
        matter for a uniform wire)."""
        return eps_core

    def core_drive(self, u: float, xi_core: float, xi: float, p: thermal.ThermalParams) -> float:
        """The input that heats the core: the wire's own `u` (`xi_core`, `xi`, `p` do not
        matter for a uniform wire)."""
        return u


class ColdEnds:
    """Ends submodel: clamps that conduct heat (`ends`), each end zone with its own temperature
    and hysteresis memory; `zones` is `ends.zones`'s table (share of the length, excess factor).
    """

    def __init__(self, zones: Sequence[tuple[float, float]]) -> None:
        self.zones = zones
        self.models: list[PreisachModel] = []

    def reset(self, surface: Hypersurface) -> None:
        """New all-off memories on `surface`, one per zone."""
        self.models = [PreisachModel(surface) for _ in self.zones]

    def strain(self, eps_core: float, T_core: float, T_amb: float, strain_of: StrainOf) -> float:
        """The wire's strain, averaged over its length: the core's `eps_core` (at `T_core` [C])
        and each zone's, `strain_of` (its memory, its temperature), at `T_amb` [C] plus its
        share of the core's excess temperature."""
        temps = ends.zone_temperatures(T_core, T_amb, self.zones)
        return (1 - sum(w for w, _ in self.zones)) * eps_core + sum(
            w * strain_of(m, T) for (w, _), m, T in zip(self.zones, self.models, temps))

    def core_drive(self, u: float, xi_core: float, xi: float, p: thermal.ThermalParams) -> float:
        """The input that heats the core as the wire's current `u` does: under voltage drive the
        current is set by the whole wire's resistance (martensite fraction `xi`), the core heats
        at its own (`xi_core`); `p` the wire's thermal parameters."""
        if p.drive == "current":
            return u
        return u * thermal.resistance(xi_core, p) / thermal.resistance(xi, p)


def ends_submodel(beta: float, length: float, diameter: float, conductivity: float,
                  h: float) -> NoEnds | ColdEnds:
    """The ends submodel of end cooling `beta` (`ends.zones`, with the wire's `length`,
    `diameter`, `conductivity` and convection `h`): `NoEnds` where it is 0."""
    table = ends.zones(beta, length, diameter, conductivity, h)
    return ColdEnds(table) if table else NoEnds()
