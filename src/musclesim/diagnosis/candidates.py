"""The candidate effects: every effect of the located components placed on their instances
(`Candidate`, `candidates`), and the refit of the best of their fits (`refine`)."""
from __future__ import annotations

from dataclasses import dataclass, replace

from musclesim.cosim import ParamRef
from musclesim.diagnosis.fitting import Free, FitJob, fit_all
from musclesim.diagnosis.effects import Effect, by_component
from musclesim.diagnosis.parameters import components_of, nominal
from musclesim.diagnosis.thresholds import REFINED

__all__ = ["Candidate", "candidates", "refine"]


@dataclass
class Candidate:
    """An effect placed on instances of its component, with its free parameters."""

    effect: Effect
    instances: tuple[str, ...]
    free: list[Free]

    @property
    def label(self) -> str:
        """The effect's name, with the instance for a per-instance effect."""
        return self.effect.name + (f" ({self.instances[0]})" if self.effect.per_instance else "")


def candidates(problem, unit, suspects):
    """The `Candidate` effects of the `suspects`' components in `unit`."""
    out = []
    for comp, insts in components_of(unit, suspects).items():
        for e in by_component(comp):
            groups = [(i,) for i in insts] if e.per_instance else [tuple(insts)]
            for g in groups:
                free = [Free(g, p.name, p.lower, p.upper, nominal(problem, ParamRef(g[0], p.name)))
                        for p in e.parameters]
                out.append(Candidate(e, g, free))
    return out


def refine(unit, cands, fits, calib, latency, fmu_dir, pmap):
    """`fits` with the REFINED candidates that fit the training part best fitted again from
    their values with every Jacobian column fresh (a refit replaces a fit only when it lowers
    the training cost). The first fits reuse the calibration's columns, taken at the calibrated
    values without the effect: quasi-Newton steps that can stop short of the joint optimum.
    Without calibration parameters every column was fresh already: `fits` as they are."""
    if not calib:
        return fits
    order = sorted((i for i, f in enumerate(fits) if f.residuals is not None and f.applicable),
                   key=lambda i: fits[i].train_gap)[:REFINED]
    again = fit_all([FitJob(unit, cands[i].free + calib, fmu_dir, x0=fits[i].x, scan=0,
                            latency=latency) for i in order], pmap)
    out = list(fits)
    for i, f in zip(order, again):
        if f.residuals is not None and f.train_gap < fits[i].train_gap:
            out[i] = replace(f, applicable=fits[i].applicable)
    return out
