"""The diagnosis report as an object: one frozen section per stage, composed into a `Report`.

Each stage of `musclesim.diagnosis.pipeline` returns its section instead of writing into a
shared dict: `GapSection` (1, the nominal model's gap), `CalibrationSection` (2),
`IsolationSection` (3, the isolation units, the located instances, the regimes),
`EvidenceSection` (4, the candidates fitted, described and weighed), `VerdictSection` (what the
diagnosis concludes) and `ShrinkageSection` (5, the held-out gap nominal, calibrated and with the
selected effects). `Report.to_json` gives report.json's document (its shape: the JSON Schema
musclesim/schemas/report.schema.json), keys in the order report.json has always had them;
`musclesim.diagnosis.report` writes it and report.md from the object. The document also says
what the report tells its reader (`musclesim.diagnosis.advice`): the values on their bounds,
the warnings naming them and the next step, derived from the sections when it is made.

The tables inside a section (one entry per signal, per unit, per effect, per candidate) stay
the JSON objects report.json holds, read by name in report.md and the benchmark; their signals
are `Signal` objects, printed (``str``) in one place, `Report.to_json` (`plain`): report.json is
where an address has its string form.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from musclesim.cosim import ParamRef, Signal
from musclesim.diagnosis.advice import next_step, warnings, with_bounds

__all__ = ["plain", "GapSection", "CalibrationSection", "IsolationSection", "FitUnitSection",
           "EvidenceSection", "VerdictSection", "ShrinkageSection", "Report"]

Table = dict[Any, Any]  # a JSON object of report.json, its signals (keys and items) typed
Column = Signal | str  # an observed signal, or a scalar-only data set's metric


def plain(value: Any) -> Any:
    """`value` with every address in it (a `Signal` or `ParamRef`, a key or an item of its
    dicts and lists) printed as report.json holds it, ``"instance.name"``.

    >>> plain({Signal("tc", "T_meas"): {"signals": [Signal("tc", "T_meas")], "gap": 0.1}})
    {'tc.T_meas': {'signals': ['tc.T_meas'], 'gap': 0.1}}
    """
    if isinstance(value, (Signal, ParamRef)):
        return str(value)
    if isinstance(value, dict):
        return {plain(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    return value


@dataclass(frozen=True)
class GapSection:
    """Section 1: the nominal model's gap with the data set's inputs replayed: per observed
    signal (or metric) its NRMSE, bias, lag, noise (`signals`), the pooled held-out gap, the
    noise floor and whether it deviates beyond it."""

    signals: dict[Column, Table]
    heldout_gap: float
    noise_floor: float
    deviates: bool

    def to_json(self) -> Table:
        """The report's ``gap``."""
        return {"signals": self.signals, "heldout_gap": self.heldout_gap,
                "noise_floor": self.noise_floor, "deviates": self.deviates}


@dataclass(frozen=True)
class CalibrationSection:
    """Section 2: the calibrated values ({"instance(s).parameter": value, interval, nominal,
    bounds}), the sensors' latencies, the held-out gap before and after, pooled and per signal.
    Only `parameters` (empty) when there was no gap to calibrate for."""

    parameters: dict[str, Table]
    latency: dict[Signal, int] | None = None
    heldout_gap_before: float | None = None
    heldout_gap_after: float | None = None
    signals: dict[Column, Table] | None = None

    @property
    def ran(self) -> bool:
        """Whether a calibration ran (else only the empty `parameters`)."""
        return self.latency is not None

    def to_json(self) -> Table:
        """The report's ``calibration``."""
        if not self.ran:
            return {"parameters": self.parameters}
        return {"parameters": self.parameters, "latency": self.latency,
                "heldout_gap_before": self.heldout_gap_before,
                "heldout_gap_after": self.heldout_gap_after, "signals": self.signals}


@dataclass(frozen=True)
class IsolationSection:
    """Section 3: the ranked table of instances (`located`), the isolation units (`units`) and
    the calibrated gap by regime with the worst windows (`regimes`)."""

    located: list[Table]
    units: list[Table]
    regimes: Table


@dataclass(frozen=True)
class FitUnitSection:
    """The unit the candidates were fitted in: its `instances`, `observed` signals and the
    sensor `latency` held ({signal: samples})."""

    instances: list[str]
    observed: list[Column]
    latency: dict[Signal, int]

    def to_json(self) -> Table:
        """The report's ``fit_unit``."""
        return {"instances": self.instances, "observed": self.observed, "latency": self.latency}


@dataclass(frozen=True)
class EvidenceSection:
    """Section 4: where the candidates were fitted (`fit_unit`), each effect's fit described
    (`effects`, ranked), the candidates weighed (`evidence`) and the cross-signal sentence
    (`consistency`, None when no two signals share a state)."""

    fit_unit: FitUnitSection
    effects: list[Table]
    evidence: Table
    consistency: str | None


@dataclass(frozen=True)
class VerdictSection:
    """What the diagnosis concludes: the verdict `name`, its one-sentence `explanation`,
    whether the gap left is unstructured (`complete`), the noise floor it was judged against,
    the effects `selected` and the effects that are `stand_ins` for a recalibration."""

    name: str
    explanation: str
    complete: bool
    noise_floor: float
    selected: list[str]
    stand_ins: list[str]


@dataclass(frozen=True)
class ShrinkageSection:
    """Section 5: per signal (and ``all``) the held-out gap nominal, calibrated and with the
    selected effects (`signals`), and the sensor latencies found (`aligned_samples`)."""

    signals: dict[Column, Table]
    aligned_samples: dict[Signal, int]


@dataclass(frozen=True)
class Report:
    """A diagnosis: the data set and model it was made of, and its sections. `isolation` is
    None when there was no gap (verdict ``none``), `evidence` None when no candidate was
    fitted (``none``, ``recalibration`` by calibration alone). `confidence` is the set,
    probabilities and gate of a calibration on a family of benches
    (`musclesim.diagnosis.confidence`), None where the scenario has none; report.json's
    ``evidence`` then holds them (``set``, ``level``, ``probabilities``, ``gate``,
    ``calibration``), beside the candidates' own posterior probabilities and their credible
    set (``credible`` at ``credible_level``)."""

    data_set: str
    scenario: str | list[str]
    scalar_only: bool
    train: list[str]
    held_out: list[str]
    gap: GapSection
    calibration: CalibrationSection
    isolation: IsolationSection | None
    evidence: EvidenceSection | None
    verdict: VerdictSection
    shrinkage: ShrinkageSection
    confidence: Table | None = None  # the calibrated set, probabilities, gate (`confidence`)

    @property
    def effects(self) -> list[Table]:
        """The effects' fits described (section 4), none when no candidate was fitted."""
        return self.evidence.effects if self.evidence is not None else []

    def to_json(self) -> Table:
        """report.json's document (addresses printed, `plain`), its keys in the order
        report.json has always had them."""
        v = self.verdict
        out: Table = {"data_set": self.data_set, "scenario": self.scenario,
                      "scalar_only": self.scalar_only,
                      "parts": {"train": self.train, "held_out": self.held_out},
                      "gap": self.gap.to_json(), "calibration": self.calibration.to_json()}
        if self.isolation is None:  # no gap
            out.update(effects=[], selected=v.selected, stand_ins=v.stand_ins, verdict=v.name,
                       explanation=v.explanation, noise_floor=v.noise_floor,
                       complete=v.complete)
        else:
            iso = self.isolation
            out.update(located=iso.located, units=iso.units, regimes=iso.regimes)
            if self.evidence is None:  # calibration alone is within the noise
                out.update(effects=[], selected=v.selected, stand_ins=v.stand_ins,
                           verdict=v.name, complete=v.complete, noise_floor=v.noise_floor,
                           explanation=v.explanation)
            else:
                e = self.evidence
                out.update(fit_unit=e.fit_unit.to_json(), effects=e.effects,
                           evidence=e.evidence, selected=v.selected, consistency=e.consistency,
                           stand_ins=v.stand_ins, verdict=v.name, explanation=v.explanation,
                           complete=v.complete, noise_floor=v.noise_floor)
        out.update(shrinkage=self.shrinkage.signals,
                   aligned_samples=self.shrinkage.aligned_samples)
        if self.confidence is not None:  # the calibrated set, the credible one kept beside
            ev = out.get("evidence", {})
            raw = {"credible": ev["set"], "credible_level": ev.get("level")} if ev else {}
            out["evidence"] = {**ev, **raw, **self.confidence}
        return _with_advice(plain(out))


def _with_advice(doc: Table) -> Table:
    """report.json document `doc` (`plain`, its own dicts) with what the report tells its
    reader (`musclesim.diagnosis.advice`): each calibrated and effect value's ``on_bound``, the
    ``warnings`` naming those on a bound and the verdict's ``next_step``; no other key
    changes."""
    cal = doc["calibration"]
    cal["parameters"] = with_bounds(cal["parameters"])
    for e in doc["effects"]:
        e["parameters"] = with_bounds(e["parameters"])
    doc["warnings"] = warnings(doc)
    doc["next_step"] = next_step(doc)
    return doc
