"""The diagnosis's files: report.json (its shape: the JSON Schema
musclesim/schemas/report.schema.json, §report-format), report.md (the same, readable) and its plots
signals.png and effects.png, all from the `Report` object (`musclesim.diagnosis.sections`)."""
from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from musclesim.cosim import replace_file, save_figure
from musclesim.diagnosis.sections import Report
from musclesim.diagnosis.stats import HELD_OUT

__all__ = ["write", "markdown"]


def _num(x, fmt=".3g"):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "-"
    return format(x, fmt)


def _iv(pair, fmt=".3g"):
    return f"[{_num(pair[0], fmt)}, {_num(pair[1], fmt)}]" if pair else "-"


def write(out: str | Path, report: Report, traces: dict[str, Any] | None = None) -> list[Path]:
    """Write `report`'s report.json, report.md and (with `traces`, as `diagnose` fills them) the
    plots into folder `out`; return the paths.

    The previous report.json goes first and the new one comes last, every file written under a
    temporary name and renamed in place: a folder holding report.json holds that report's files,
    whenever the writing is stopped.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    paths = [out / "report.json", out / "report.md"]
    paths[0].unlink(missing_ok=True)
    plots = []
    if traces and traces.get("unit") is not None and not report.scalar_only:
        plots.append(_plot_signals(out / "signals.png", report, traces))
    if report.effects:
        plots.append(_plot_effects(out / "effects.png", report))
    replace_file(paths[1], markdown(report, [p.name for p in plots]))
    replace_file(paths[0], json.dumps(report.to_json(), indent=1, default=float) + "\n")
    return paths + plots


def markdown(report: Report, plots: Sequence[str] = ()) -> str:
    """`report` as Markdown (with `plots`, file names of images in the same folder): every number
    with its unit (a gap, a share of its signal's range, is of unit 1), the values on a bound
    flagged and named in a warnings paragraph, the verdict's paragraph ending in its next step
    (report.json's ``warnings`` and ``next_step``)."""
    v = report.verdict
    doc = report.to_json()
    L = [f"# Diagnosis of {report.data_set}", "",
         f"Scenario: {report.scenario}. Training part: {', '.join(report.train)}; "
         f"held out: {', '.join(report.held_out)}. Gaps are RMS residuals as a share of each "
         "signal's measured range (unit 1; 0.01 = 1 % of the range).", "",
         f"## Verdict: **{v.name}**" + ("" if v.complete else " (incomplete)"), "",
         f"{v.explanation}. Next step: {doc['next_step']}.", ""]
    L += _md_confidence(report.confidence)
    if doc["warnings"]:
        L += ["**Warnings** (values on a bound of their range):", ""]
        L += [f"- {w}." for w in doc["warnings"]] + [""]
    L += (_md_gap(report) + _md_calibration(doc) + _md_where(report) + _md_which(report, doc)
          + _md_shrinkage(report))
    L += [""] + [f"![{p}]({p})" for p in plots]
    return "\n".join(L) + "\n"


def _md_confidence(conf):
    """The calibrated set, its level, the causes' probabilities and the gate (`conf`, the
    report's `confidence`, None without a calibration)."""
    if conf is None:
        return []
    gate, cal = conf["gate"], conf["calibration"]
    probs = ", ".join(f"{k} {p:.2f}" for k, p in sorted(conf["probabilities"].items(),
                                                          key=lambda kv: -kv[1]) if p >= 0.005)
    level = f"{conf['level'] * 100:.0f} %"
    L = [f"**Calibrated set ({level}): {', '.join(conf['set']) or 'empty'}.** "
         f"On benches of the calibrated family ({cal['name']}, {cal['family'].get('cases')} "
         f"cases), a set made this way holds the true cause at least {level} of the "
         f"time, for every cause. Calibrated probabilities: {probs}.", ""]
    if gate["outside"]:
        L += [f"**Outside the calibrated family** (p = {gate['p_value']:.3f}): this bench is "
              "unlike the benches the set was calibrated on; the set above is the nearest one and "
              "its guarantee does not hold here.", ""]
    return L


def _md_gap(report):
    """Section 1: the whole model's gap, per signal (or metric)."""
    g = report.gap
    L = ["## 1. The gap (whole model, inputs replayed)", "",
         f"Pooled held-out gap {_num(g.heldout_gap)} (normalised by each signal's range, unit "
         f"1); noise floor {_num(g.noise_floor)}; "
         f"{'deviates' if g.deviates else 'within the noise'}.", ""]
    if report.scalar_only:
        L += ["| metric | relative error per experiment [1] |", "|---|---|"]
        L += [f"| {c} | {', '.join(_num(x) for x in e['relative_error'])} |"
              for c, e in g.signals.items()]
    else:
        L += ["| signal | NRMSE [1] | held-out NRMSE [1] | bias (data - model) | lag [s] | "
              "noise [1] |",
              "|---|---|---|---|---|---|"]
        L += [f"| {c} | {_num(e['nrmse'])} | {_num(e['nrmse_heldout'])} | {_num(e['bias'])}"
              f"{'' if e['unit'] == '1' else ' ' + e['unit']} | {_num(e.get('lag'))} | "
              f"{_num(e['noise'])} |"
              for c, e in g.signals.items()]
    return L


def _md_calibration(doc):
    """Section 2 of report.json document `doc`: the calibrated nominal values with their units,
    intervals and bounds (one on its bound flagged), the gap before and after."""
    c = doc["calibration"]
    L = ["", "## 2. Calibration (training part; everything below is judged against it)", ""]
    if not c["parameters"]:
        return L + ["Nothing calibrated (no gap, or no calibration parameter in the model)."]
    L += [f"Held-out gap {_num(c['heldout_gap_before'])} nominal, "
          f"{_num(c['heldout_gap_after'])} calibrated (unit 1).", "",
          "| parameter | unit | nominal | calibrated [95 % interval] | bounds | on a bound |",
          "|---|---|---|---|---|---|"]
    L += [f"| {k} | {v.get('unit', '-')} | {_num(v['nominal'], '.5g')} | "
          f"{_num(v['value'], '.5g')} {_iv(v['interval'], '.5g')} | "
          f"{_iv([v['lower'], v['upper']], '.5g')} | {_bound(v)} |"
          for k, v in c["parameters"].items()]
    L += ["", "| signal | held-out gap nominal [1] | calibrated [1] |", "|---|---|---|"]
    L += [f"| {k} | {_num(v['before'])} | {_num(v['after'])} |"
          for k, v in (c.get("signals") or {}).items()]
    return L


def _bound(entry):
    """A report table's cell saying whether fitted value `entry` sits on a bound."""
    return "**yes**: a model-form warning" if entry.get("on_bound") else "no"


def _md_where(report):
    """Section 3: the isolation units, the located instances, the regimes, the worst windows."""
    L = ["", "## 3. Where (calibrated)", ""]
    iso = report.isolation
    if iso is not None and iso.units:
        L += ["Isolation units (each re-simulated with the measured signals feeding it replayed):",
              "", "| unit | observed | held-out gap [1] | noise floor [1] | deviates |",
              "|---|---|---|---|---|"]
        L += [f"| {' + '.join(u['instances'])} | {_names(u['observed'])} | "
              f"{_num(u['heldout_gap'])} | {_num(u['noise_floor'])} | {u['deviates']} |"
              for u in iso.units]
        L += ["", "| instance | component | isolated gap [1] | located | exonerated |",
              "|---|---|---|---|---|"]
        L += [f"| {r['instance']} | {r['component']} | {_num(r['isolated_gap'])} | "
              f"{r['located']} | {r['exonerated']} |" for r in iso.located]
    else:
        L += ["No component can be isolated (scalar-only data or no measured internal signal)."]
    reg = iso.regimes if iso is not None else {}
    if reg.get("by_regime"):
        L += ["", "Calibrated gap by regime:", "",
              "| regime | share of samples [1] | gap [1] |",
              "|---|---|---|"]
        L += [f"| {k} ({v['description']}) | {_num(v['fraction'], '.2f')} | {_num(v['gap'])} |"
              for k, v in reg["by_regime"].items()]
    if reg.get("worst_windows"):
        L += ["", "Worst windows: " + "; ".join(
            f"{w['experiment']} {w['t0']:.2f}-{w['t1']:.2f} s (gap {_num(w['gap'])})"
            for w in reg["worst_windows"]) + "."]
    return L


def _md_which(report, doc):
    """Section 4: the candidates weighed by evidence, then each effect's fit described (its
    values with their units and bound flags from report.json document `doc`)."""
    L = ["", "## 4. Which cause: the evidence", ""]
    ev = report.evidence
    if ev is None or not ev.effects:
        return L + ["No candidate was fitted."]
    fu = ev.fit_unit
    L += _md_evidence(ev.evidence, fu.observed)
    L += ["", "### Each effect's fit", "",
          f"Fitted in {' + '.join(fu.instances)} on the training part together with "
          "the calibration parameters; described on the held-out part against calibration "
          "alone, on the signals each effect can change (the gain and its bootstrap interval, "
          "whether it gains most in the regime it predicts, how far the calibration makes its "
          "signature too: 1 not at all, 10 and more hardly told apart). These numbers describe "
          "the fits; the evidence above weighs them.", "",
          "| rank | effect | fitted values [95 % interval] | judged on | gap there: calibrated "
          "-> with effect [1] | gain [95 %] [1] | pooled gap [1] | regime gain ratio [1] | "
          "collinearity with calibration [1] | gains clearly |",
          "|---|---|---|---|---|---|---|---|---|---|"]
    for i, (e, shown) in enumerate(zip(ev.effects, doc["effects"]), 1):
        vals = "; ".join(_fitted(n, p) for n, p in shown["parameters"].items())
        j = e.get("judged") or {}
        sig = e["signature"]
        mark = " *" if e.get("baseline", "calibration") != "calibration" else ""
        L.append(f"| {i} | {e['label']}{mark} | {vals} | {_names(j.get('signals', []))} | "
                 f"{_num(j.get('before'))} -> {_num(j.get('after'))} | "
                 f"{_num(j.get('gain'), '.2f')} {_iv(j.get('interval'), '.2f')} | "
                 f"{_num(e['heldout_gap_before'])} -> {_num(e['heldout_gap_after'])} | "
                 f"{sig['regime']}: {_num(sig['gain_ratio'], '.2f')} | {_alias(e)} | "
                 f"{e['counts']} |")
    L += ["", "Per signal, held-out gap calibrated -> with the effect [1]:", "",
          "| effect | " + " | ".join(map(str, fu.observed)) + " |",
          "|---|" + "---|" * len(fu.observed)]
    for e in ev.effects:
        ps = e.get("per_signal", {})
        L.append(f"| {e['label']} | " + " | ".join(
            f"{_num(ps[c]['before'])} -> {_num(ps[c]['after'])}" if c in ps else "-"
            for c in fu.observed) + " |")
    if ev.consistency:
        L += ["", "Cross-signal evidence: " + ev.consistency]
    return L


def _md_evidence(ev, signals):
    """The evidence table of section `ev` (held-out gaps of the fit unit's observed
    `signals`): each candidate's probability, log evidence, predictive check and held-out gaps,
    the credible set, why the others are out, the symmetries."""
    if not ev:
        return []
    L = ["Each candidate (calibration alone, each effect of the located components with the "
         "calibration parameters, a pair where the most probable leaves a structured gap) is "
         "weighed by its evidence on the training part: its marginal likelihood under a model of "
         "the mismatch calibration leaves (per signal an autoregressive process), with every "
         "candidate equally probable beforehand (a pair a tenth as probable). The predictive "
         "check is the RMS of the standardised held-out innovations (about 1: described; above "
         "3: not).", "",
         "| candidate | probability | log evidence | predictive check | held-out gap [1] "
         + " | ".join(map(str, signals)) + " |",
         "|---|---|---|---|" + "---|" * len(signals)]
    for c in ev["candidates"]:
        gaps = " | ".join(_num(c["heldout_gap"].get(s)) for s in signals)
        L.append(f"| {c['name']} | {c['probability']:.3f} | {c['log_evidence']:.1f} | "
                 f"{_num(c['predictive'], '.2f')} | {gaps} |")
    L += ["", f"Credible set ({ev.get('level', 0.9):.0%} of the probability): "
          f"**{', '.join(ev['set'])}**."]
    out = [c for c in ev["candidates"] if c.get("excluded")]
    if out:
        L += ["", "Left out of the set: " + "; ".join(f"{c['name']} ({c['excluded']})"
                                                   for c in out) + "."]
    for sym in ev.get("symmetries", []):
        L += ["", f"Symmetry: {sym['candidates'][0]} is a recalibration of "
                  f"{', '.join(sym['with']) or 'nothing'} on these data (what the calibration "
                  f"cannot make of it: {sym['chi2']:.2g} noise variances); to tell them apart, "
                  + "; or ".join(sym["breaks_with"]) + "."]
    return L


def _fitted(name, p):
    """Effect parameter `name`'s fitted value `p`: value and interval in its unit, flagged
    when on a bound."""
    unit = p.get("unit")
    return (f"{name} = {_num(p['value'], '.4g')} {_iv(p['interval'], '.3g')}"
            + ("" if unit in (None, "1") else f" {unit}")
            + (" (**on its bound**)" if p.get("on_bound") else ""))


def _names(signals):
    """`signals` printed, comma-separated."""
    return ", ".join(map(str, signals))


def _alias(entry):
    a = entry.get("aliasing")
    return "-" if not a else f"{a['index']:.3g} ({', '.join(a['with'])})"


def _md_shrinkage(report):
    """Section 5: the held-out gap per signal nominal, calibrated, with the selected effects."""
    L = ["", "## 5. How far it shrinks (held-out part, every measured signal replayed)", "",
         f"Selected: {', '.join(report.verdict.selected or ['nothing'])}.", "",
         "| signal | nominal [95 %] [1] | calibrated [1] | with the selected effects [95 %] [1] "
         "|",
         "|---|---|---|---|"]
    L += [f"| {c} | {_num(s['before'])} {_iv(s['interval_before'])} | "
          f"{_num(s.get('calibrated'))} | {_num(s['after'])} {_iv(s['interval_after'])} |"
          for c, s in report.shrinkage.signals.items()]
    shifted = {c: n for c, n in report.shrinkage.aligned_samples.items() if n}
    if shifted:
        L += ["", "Sensor channels compared allowing for acquisition latency: " + ", ".join(
            f"{c} {n} sample(s) behind" for c, n in shifted.items()) + "."]
    return L


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _plot_signals(path, report, traces):
    plt = _plt()
    unit = traces["unit"]
    cols = list(unit.observed)
    fig, axes = plt.subplots(len(cols), 1, sharex=True, squeeze=False,
                             figsize=(9, 2.3 * len(cols) + 0.8))
    for ax, c in zip(axes[:, 0], cols):
        for i, run in enumerate(unit.runs):
            t = run.t0 + run.time
            first = i == 0
            ax.plot(t, run.measured[c], color="0.3", lw=0.8, label="measured" if first else None)
            ax.plot(t, traces["nominal"][i][c], color="tab:red", lw=0.8,
                    label="nominal model" if first else None)
            if traces.get("calibrated") is not None:
                ax.plot(t, traces["calibrated"][i][c], color="tab:orange", lw=0.8,
                        label="calibrated" if first else None)
            if report.verdict.selected:
                ax.plot(t, traces["selected"][i][c], color="tab:green", lw=0.8, ls="--",
                        label=" + ".join(report.verdict.selected) if first else None)
            held = run.part == HELD_OUT
            if held.any():
                ax.axvspan(t[held][0], t[held][-1], color="tab:blue", alpha=0.07,
                           label="held out" if first else None)
        unit_name = report.gap.signals.get(c, {}).get("unit", "")
        ax.set_ylabel(f"{c} [{unit_name}]", fontsize=8)
        ax.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=7, loc="best")
    axes[-1, 0].set_xlabel("time [s]")
    fig.suptitle(f"verdict: {report.verdict.name}", fontsize=10)
    fig.tight_layout()
    save_figure(fig, path, dpi=100)
    plt.close(fig)
    return path


def _plot_effects(path, report):
    plt = _plt()
    es = report.effects
    fig, ax = plt.subplots(figsize=(8, 0.45 * len(es) + 1.5))
    y = np.arange(len(es))[::-1]
    ax.barh(y, [e["heldout_gap_after"] for e in es],
            color=["tab:green" if e["counts"] else "0.6" for e in es])
    ax.axvline(report.gap.heldout_gap, color="tab:red", lw=1, label="nominal")
    ax.axvline(es[0]["heldout_gap_before"], color="tab:orange", lw=1, ls="--",
               label="calibrated")
    ax.axvline(report.verdict.noise_floor, color="0.3", lw=1, ls=":", label="noise floor")
    ax.set_yticks(y, [e["label"] for e in es], fontsize=8)
    ax.set_xlabel("pooled held-out gap [1] with the effect and calibration (green: counts)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, path, dpi=100)
    plt.close(fig)
    return path
