"""Linear analysis of the crawler body (§two-mass): its controllability with the actuator force
only and with all three inputs, with python-control."""
from __future__ import annotations

from typing import Any

import control as ct
import numpy as np

from musclesim.components.crawler.body import BodyParams, state_space

STATES = ["x1", "v1", "x2", "v2"]
INPUTS = ["f_a", "f1", "f2"]


def crawler_system(p: BodyParams = BodyParams()) -> ct.StateSpace:
    """The crawler body of parameters `p` as a python-control state-space system with full state
    output."""
    A, B = state_space(p)
    return ct.ss(A, B, np.eye(4), np.zeros((4, 3)), states=STATES, inputs=INPUTS,
                 outputs=STATES, name="crawler")


def _row_echelon_basis(Q: np.ndarray, tol: float = 1e-9) -> np.ndarray:
    """Basis of the column space of Q in reduced row-echelon form (leading ones, like §two-mass)."""
    M = Q.T
    pivots: list[int] = []
    for j in range(M.shape[1]):
        if np.linalg.matrix_rank(M[:, pivots + [j]], tol) > len(pivots):
            pivots.append(j)
        if len(pivots) == M.shape[0]:
            break
    R = np.linalg.solve(M[:, pivots], M)
    R[np.abs(R) < tol] = 0.0
    return R


def crawler(p: BodyParams = BodyParams()) -> dict[str, Any]:
    """Controllability of the crawler body of parameters `p` with the actuator force only and
    with all three inputs.

    Returns
    -------
    dict
        ``rank_fa_only`` and ``rank_all_inputs`` (ranks of the controllability matrices),
        ``controllable_subspace_fa_only`` (basis vectors over ``states``, reduced row-echelon
        form), ``centre_of_mass_reachable_fa_only`` (False when f_a alone cannot move the centre
        of mass), plus the states, inputs and parameters used.

    Examples
    --------
    >>> r = crawler()
    >>> r["rank_fa_only"], r["rank_all_inputs"]
    (2, 4)
    """
    sys = crawler_system(p)
    ctrb_fa = ct.ctrb(sys.A, sys.B[:, :1])
    ctrb_all = ct.ctrb(sys.A, sys.B)
    tol = 1e-9 * np.linalg.norm(ctrb_all)
    rank_fa = int(np.linalg.matrix_rank(ctrb_fa, tol))
    U, _, _ = np.linalg.svd(ctrb_fa)
    basis = _row_echelon_basis(U[:, :rank_fa])
    # centre-of-mass position and velocity as linear functionals of the state
    cm = np.array([[p.m1, 0, p.m2, 0], [0, p.m1, 0, p.m2]]) / (p.m1 + p.m2)
    cm_gain = float(np.abs(cm @ ctrb_fa).max())
    return {
        "system": "crawler",
        "reference": "§two-mass",
        "parameters": {"m1": p.m1, "m2": p.m2, "k": p.k, "c": p.c},
        "states": STATES,
        "inputs": INPUTS,
        "rank_fa_only": rank_fa,
        "rank_all_inputs": int(np.linalg.matrix_rank(ctrb_all, tol)),
        "controllable_subspace_fa_only": basis.tolist(),
        "centre_of_mass_reachable_fa_only": bool(cm_gain > tol),
    }


def format_crawler(report: dict[str, Any]) -> str:
    """Human-readable text of a `crawler` report `report`."""
    vec = lambda v: "[" + ", ".join(f"{x:g}" for x in v) + "]"
    n = len(report["states"])
    lines = [
        f"Crawler body (§two-mass), states [{', '.join(report['states'])}], "
        f"m1 = {report['parameters']['m1']:g} kg, m2 = {report['parameters']['m2']:g} kg",
        f"controllability rank, f_a only:        {report['rank_fa_only']} of {n}",
        f"controllability rank, f_a, f1 and f2:  {report['rank_all_inputs']} of {n}",
        "controllable subspace with f_a only:  span of "
        + ", ".join(vec(v) for v in report["controllable_subspace_fa_only"]),
        "centre of mass movable with f_a only: "
        + ("yes" if report["centre_of_mass_reachable_fa_only"] else
           "no (no locomotion without friction)"),
    ]
    return "\n".join(lines)
