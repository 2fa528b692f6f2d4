"""Damped Gauss-Newton on eq. 25 as written, from the fast search's optimum.

The grid search (`tracker.mltma.search`) minimises the pseudo-linear form of the bearing term
(weights from the earlier range estimates); this polish makes the estimate the local minimum of
eq. 25 with the exact bearing residuals over every bearing of the tack (analytic Jacobian,
`tracker.mltma.eq25.residuals`). A step is kept only where it lowers the functional; speed
stays in the search's interval, range between ``range_min_m`` and ``range_max_m``.
"""

from __future__ import annotations

import numpy as np

from tracker.mltma.eq25 import Eq25Estimate, Eq25Terms, residuals, speed_interval_mps
from tracker.mltma.window import TackWindow


def polish(window: TackWindow, start: Eq25Estimate, terms: Eq25Terms, *, range_min_m: float,
           range_max_m: float, speed_span_sd: float, iterations: int) -> Eq25Estimate:
    """Up to ``iterations`` Levenberg-damped Gauss-Newton steps in (course, speed, range).

    Stops early once every row's step is negligible (1e-3 deg, 1e-4 m/s, 1e-5 of the range).

    Parameters
    ----------
    window : TackWindow
        The rows' tacks up to the current cycle.
    start : Eq25Estimate
        The search's estimate; its sds are kept.
    terms : Eq25Terms
    range_min_m, range_max_m : float
        Range bounds, m.
    speed_span_sd : float
        The search's speed interval, mV +- this many sV (`speed_interval_mps`).
    iterations : int
        `MLParams.polish_iters`.

    Returns
    -------
    Eq25Estimate
        Course in [0, 360).
    """
    k, v, r = start.course_deg.copy(), start.speed_mps.copy(), start.range_m.copy()
    v_lo, v_hi = speed_interval_mps(terms, speed_span_sd)
    f, J = residuals(window, terms, k, v, r, jacobian=True)
    cost = np.square(f).sum(1)
    lam = np.full(len(k), 1e-3)
    for it in range(iterations):
        Jt = J.transpose(0, 2, 1)
        JtJ = Jt @ J
        g = (Jt @ f[:, :, None])[:, :, 0]
        diag = np.einsum("bii->bi", JtJ)
        A = JtJ + (lam[:, None] * np.maximum(diag, 1e-12))[:, :, None] * np.eye(3)[None]
        try:
            step = -np.linalg.solve(A, g[:, :, None])[:, :, 0]
        except np.linalg.LinAlgError:
            break
        if np.all((np.abs(step[:, 0]) < 1e-3) & (np.abs(step[:, 1]) < 1e-4)
                  & (np.abs(step[:, 2]) < 1e-5 * r)):
            break                                        # converged everywhere
        k1 = k + step[:, 0]
        v1 = np.clip(v + step[:, 1], v_lo, v_hi)
        r1 = np.clip(r + step[:, 2], range_min_m, range_max_m)
        last = it == iterations - 1
        out = residuals(window, terms, k1, v1, r1, jacobian=not last)
        f1, J1 = (out, None) if last else out
        c1 = np.square(f1).sum(1)
        ok = np.isfinite(c1) & (c1 < cost)
        k, v, r = np.where(ok, k1, k), np.where(ok, v1, v), np.where(ok, r1, r)
        if last:
            break
        f = np.where(ok[:, None], f1, f)
        J = np.where(ok[:, None, None], J1, J)
        cost = np.where(ok, c1, cost)
        lam = np.where(ok, lam * 0.3, lam * 10.0)
    return start._replace(course_deg=np.mod(k, 360.0), speed_mps=v, range_m=r)
