"""The diagnosis's blind test lab: virtual benches with hidden causes, sealed keys, scores.

Above the diagnosis (`musclesim.diagnosis`), whose public interface it uses and never changes:
``run_blind_benchmark`` records cases on virtual hardware (the library's own FMUs with a hidden
effect, or benches written apart from the library, `benches`), writes their data without labels
and a sealed key, diagnoses every case and scores the verdicts against the key.

Modules: blind (the benchmark run: record, diagnose blind, score), cases (the own benches' cases:
hidden effects, decoys, the plan), recording (the own benches' virtual hardware, a case written as
a data set), scoring (the oracle, the scores against the key, scores.json), plan (the independent
benches' cases: conditions, hidden causes, the oracle), benches.sma (with its hysteresis,
benches.sma_kinetics) and benches.crawler (an SMA tracking bench and a pneumatic crawler written
apart from the library, numpy and scipy only), family and family_crawler (those benches' families
of forms, with our own model a member), calibrate (the diagnosis's sets calibrated on a family's
pool of cases, and their scores).
"""
from musclesim.benchmark.blind import run as run_blind_benchmark

__all__ = ["run_blind_benchmark"]
