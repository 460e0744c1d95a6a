"""The candidates' refit on hand-made fits (no FMU)."""
import math
from types import SimpleNamespace

from musclesim.diagnosis.candidates import refine
from musclesim.diagnosis.fitting import FitResult
from musclesim.diagnosis.thresholds import REFINED


def test_refine_refits_the_best_two_from_their_values_and_keeps_only_improvements():
    def fit(train, x, applicable=True, residuals=()):
        return FitResult(x, [], residuals, train, math.inf, applicable, 1, None, {})

    first = [fit(0.5, [1.0]), fit(0.2, [2.0]), fit(0.1, [3.0], applicable=False),
             fit(0.3, [4.0]), fit(0.05, [5.0], residuals=None)]  # a failed fit
    cands = [SimpleNamespace(free=[f"effect{i}"]) for i in range(len(first))]
    asked = []

    def pmap(task, jobs):  # a refit improves the second (0.2 -> 0.15), not the fourth
        asked.extend(jobs)
        return [fit({2.0: 0.15, 4.0: 0.35}[job.x0[0]], [job.x0[0] + 0.5]) for job in jobs]

    out = refine("unit", cands, first, ["calib"], {"tc": 1}, "fmus", pmap)
    # the applicable, successful fits with the lowest training cost, from their own values,
    # every Jacobian column fresh (known None) and the calibration's latency held
    assert REFINED == 2 and [job.x0 for job in asked] == [[2.0], [4.0]]
    assert all(job.free == [f"effect{i}", "calib"] and job.known is None
               and job.latency == {"tc": 1} and job.scan == 0 for job, i in zip(asked, (1, 3)))
    assert out[1].train_gap == 0.15 and out[1].x == [2.5]
    assert out[3] is first[3] and out[0] is first[0]
    assert refine("unit", cands, first, [], {}, "fmus", pmap) is first  # nothing calibrated
