"""A stationary target's position from bearings: crossing, least squares, mean (Schmidt et al.).

Two bearings give the crossing fix x = P^-1 b (eqs. 6-8), n bearings the least-squares solution
of the n equations (4), and the mean of the crossings of consecutive pairs is eq. 29. A fix whose
conditioning number u (eq. 11) exceeds a limit, or whose bearing lines cross behind an observer,
raises `LocateError` instead of being computed.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field

import numpy as np

from tracker.errors import LocateError
from tracker.locate.bearings import Bearings
from tracker.locate.choices import DEFAULT_MAX_U, FixMethod
from tracker.locate.geometry import (
    SAME_POSITION_M,
    bearing_system,
    bearing_to_deg,
    crossing_point,
    pair_conditioning,
    wrap_deg,
)

log = logging.getLogger(__name__)


def _empty() -> np.ndarray:
    return np.empty(0)


@dataclass(frozen=True, slots=True, kw_only=True)
class LocateResult:
    """A stationary target's estimated position and how well the bearings condition it.

    Attributes
    ----------
    x_m, y_m : float
        Estimated target position, m.
    method : FixMethod
        The estimator used.
    u : float
        Conditioning number (eq. 11) of the system solved: P of the two bearings (crossing),
        the n x 2 matrix P (lsq), the largest u of the pairs used (mean).
    determinant : float
        |P| = sin(alpha1 - alpha2) (eq. 10) for the crossing; sqrt(det(P^T P)) (the product of
        the singular values, |P| for two bearings) for lsq; the pairs' determinant of smallest
        magnitude for the mean.
    n_bearings : int
        Number of bearings given.
    pair_rows : tuple of (int, int)
        0-based rows of the bearing pairs whose crossings make the fix (crossing and mean);
        empty for lsq.
    pair_x_m, pair_y_m, pair_u, pair_determinant : ndarray
        Crossing, u and |P| of each pair in ``pair_rows``.
    pairs_skipped : int
        Consecutive pairs left out of the mean (ill-conditioned or crossing behind an observer).
    residual_deg : ndarray
        Measured minus estimated bearing for each row, deg in [-180, 180).
    """

    x_m: float
    y_m: float
    method: FixMethod
    u: float
    determinant: float
    n_bearings: int
    pair_rows: tuple[tuple[int, int], ...] = ()
    pair_x_m: np.ndarray = field(default_factory=_empty)
    pair_y_m: np.ndarray = field(default_factory=_empty)
    pair_u: np.ndarray = field(default_factory=_empty)
    pair_determinant: np.ndarray = field(default_factory=_empty)
    pairs_skipped: int = 0
    residual_deg: np.ndarray = field(default_factory=_empty)

    @property
    def residual_rms_deg(self) -> float:
        """RMS bearing residual, deg."""
        return float(np.sqrt(np.mean(self.residual_deg ** 2))) if self.residual_deg.size else 0.0


def _check_positions(bearings: Bearings) -> None:
    n = len(bearings)
    if n < 2:
        raise LocateError(f"{bearings.source}: need at least 2 bearings to locate a stationary "
                          f"target, got {n}")
    x, y = bearings.obs_x_m, bearings.obs_y_m
    keys = np.column_stack([np.round(x / SAME_POSITION_M), np.round(y / SAME_POSITION_M)])
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.ravel()
    repeated = np.flatnonzero(first[inverse] != np.arange(n))
    if repeated.size:
        j = int(repeated[0])
        i = int(first[inverse[j]])
        raise LocateError(f"{bearings.source}: rows {i + 1} and {j + 1} have the same observer "
                          f"position (obs_x_m, obs_y_m) = ({x[j]:g}, {y[j]:g}) m; bearings from "
                          f"one position do not cross at the target")


def _ill_conditioned(source: str, what: str, u: float, max_u: float, delta_deg: float | None):
    diff = "" if delta_deg is None else f" (bearing difference {delta_deg:.3g} deg)"
    return LocateError(f"{source}: {what} are parallel or nearly so{diff}: conditioning number "
                       f"u = {u:.4g} exceeds the limit {max_u:g} (eq. 11); no fix")


def _check_ahead(bearings: Bearings, x_m: float, y_m: float, what: str, *, rows: np.ndarray,
                 min_behind: int) -> None:
    """Reject a fix behind ``min_behind`` or more of the observers of ``rows`` (a ghost fix)."""
    a = np.radians(bearings.bearing_deg[rows])
    r = ((x_m - bearings.obs_x_m[rows]) * np.sin(a)
         + (y_m - bearings.obs_y_m[rows]) * np.cos(a))  # range along each bearing
    behind = np.flatnonzero(r <= 0.0)
    if behind.size >= min_behind:
        k = int(behind[np.argmin(r[behind])])
        raise LocateError(
            f"{bearings.source}: the {what} fix ({x_m:.1f}, {y_m:.1f}) m lies behind the observer "
            f"of row {rows[k] + 1} ({r[k]:.4g} m along its bearing "
            f"{bearings.bearing_deg[rows[k]]:g} deg): the bearing lines cross on the wrong side; "
            f"no fix")


def _residuals(bearings: Bearings, x_m: float, y_m: float) -> np.ndarray:
    seen = bearing_to_deg(bearings.obs_x_m, bearings.obs_y_m, x_m, y_m)
    return wrap_deg(bearings.bearing_deg - seen)


def _pair_fixes(bearings: Bearings, rows_i: np.ndarray, rows_j: np.ndarray):
    x, y, b = bearings.obs_x_m, bearings.obs_y_m, bearings.bearing_deg
    fx, fy, r1, r2, det = crossing_point(x[rows_i], y[rows_i], b[rows_i],
                                         x[rows_j], y[rows_j], b[rows_j])
    u = pair_conditioning(b[rows_i] - b[rows_j])
    return fx, fy, r1, r2, det, u


def crossing_fix(bearings: Bearings, *, max_u: float = DEFAULT_MAX_U) -> LocateResult:
    """Crossing of the last two bearing lines, x = P^-1 b (eqs. 6-8).

    Parameters
    ----------
    bearings : Bearings
        Two or more bearings; the last two are used (the current fix of algorithm (23)).
    max_u : float
        Largest conditioning number (eq. 11) accepted.

    Returns
    -------
    LocateResult
        With u (eq. 11) and |P| = sin(alpha1 - alpha2) (eq. 10).

    Raises
    ------
    LocateError
        Fewer than two bearings, the same observer position twice, bearing lines parallel or
        nearly so (u > max_u), or lines that cross behind an observer.
    """
    _check_positions(bearings)
    n = len(bearings)
    i, j = n - 2, n - 1
    fx, fy, _, _, det, u = _pair_fixes(bearings, np.array([i]), np.array([j]))
    delta = float(wrap_deg(bearings.bearing_deg[i] - bearings.bearing_deg[j]))
    if not u[0] <= max_u:
        raise _ill_conditioned(bearings.source, f"the bearing lines of rows {i + 1} and {j + 1}",
                               float(u[0]), max_u, delta)
    x_m, y_m = float(fx[0]), float(fy[0])
    _check_ahead(bearings, x_m, y_m, "crossing", rows=np.array([i, j]), min_behind=1)
    return LocateResult(x_m=x_m, y_m=y_m, method=FixMethod.CROSSING, u=float(u[0]),
                        determinant=float(det[0]), n_bearings=n, pair_rows=((i, j),),
                        pair_x_m=fx, pair_y_m=fy, pair_u=u, pair_determinant=det,
                        residual_deg=_residuals(bearings, x_m, y_m))


def lsq_fix(bearings: Bearings, *, max_u: float = DEFAULT_MAX_U) -> LocateResult:
    """Least-squares solution of the n equations (4), P x = b with P of shape (n, 2).

    Each row of P is a unit vector, so the fix minimises the sum of squared perpendicular
    distances from the bearing lines. For two bearings it equals the crossing (eq. 8).

    Parameters
    ----------
    bearings : Bearings
        Two or more bearings.
    max_u : float
        Largest conditioning number (eq. 11) of the n x 2 matrix P accepted.

    Returns
    -------
    LocateResult
        ``u`` of the n x 2 matrix; ``determinant`` the product of its singular values.

    Raises
    ------
    LocateError
        Fewer than two bearings, the same observer position twice, all bearing lines
        parallel or nearly so (u > max_u), or a fix behind at least half of the observers
        (for two bearings: behind either), where the lines cross on the wrong side.
    """
    _check_positions(bearings)
    p, b = bearing_system(bearings.obs_x_m, bearings.obs_y_m, bearings.bearing_deg)
    # Solve about the mean observer position so that large coordinates lose no precision.
    x_ref, y_ref = float(np.mean(bearings.obs_x_m)), float(np.mean(bearings.obs_y_m))
    b_local = b - p @ np.array([x_ref, y_ref])
    sv = np.linalg.svd(p, compute_uv=False)
    # s_min at rounding level means exactly parallel lines: report u = inf, not 1e16
    u = float(sv[0] / sv[-1]) if sv[-1] > 8.0 * np.finfo(float).eps * sv[0] else math.inf
    if not u <= max_u:
        spread = float(np.ptp(np.unwrap(np.radians(bearings.bearing_deg))))
        raise _ill_conditioned(bearings.source, f"the {len(bearings)} bearing lines", u, max_u,
                               math.degrees(spread))
    sol, *_ = np.linalg.lstsq(p, b_local, rcond=None)
    x_m, y_m = float(sol[0] + x_ref), float(sol[1] + y_ref)
    n = len(bearings)
    _check_ahead(bearings, x_m, y_m, "least-squares", rows=np.arange(n),
                 min_behind=(n + 1) // 2)
    return LocateResult(x_m=x_m, y_m=y_m, method=FixMethod.LSQ, u=u,
                        determinant=float(sv[0] * sv[1]), n_bearings=len(bearings),
                        residual_deg=_residuals(bearings, x_m, y_m))


def mean_fix(bearings: Bearings, *, max_u: float = DEFAULT_MAX_U) -> LocateResult:
    """Mean of the crossing fixes of consecutive bearing pairs (eq. 29).

    The pairs are (1, 2), (2, 3), ..., as in step 6 of algorithm (23). A pair whose u exceeds
    ``max_u`` or whose lines cross behind an observer is left out (and counted in
    ``pairs_skipped``, logged at INFO level).

    Parameters
    ----------
    bearings : Bearings
        Two or more bearings, in time order.
    max_u : float
        Largest conditioning number (eq. 11) of a pair accepted.

    Returns
    -------
    LocateResult
        ``u`` the largest and ``determinant`` the smallest-magnitude |P| of the pairs used.

    Raises
    ------
    LocateError
        Fewer than two bearings, the same observer position twice, or no usable pair.
    """
    _check_positions(bearings)
    n = len(bearings)
    rows_i, rows_j = np.arange(n - 1), np.arange(1, n)
    fx, fy, r1, r2, det, u = _pair_fixes(bearings, rows_i, rows_j)
    good_u = u <= max_u
    ahead = (r1 > 0.0) & (r2 > 0.0)
    keep = good_u & ahead
    skipped = int(np.count_nonzero(~keep))
    if not keep.any():
        k = int(np.argmin(u))
        if not good_u.any():
            raise _ill_conditioned(bearings.source,
                                   f"the bearing lines of every consecutive pair ({n - 1})",
                                   float(u[k]), max_u,
                                   float(wrap_deg(bearings.bearing_deg[k]
                                                  - bearings.bearing_deg[k + 1])))
        raise LocateError(f"{bearings.source}: every well-conditioned pair of consecutive "
                          f"bearings crosses behind an observer (e.g. rows {k + 1} and {k + 2}); "
                          f"no fix")
    if skipped:
        log.info("%s: %d of %d consecutive bearing pairs left out of the mean (u > %g or "
                 "crossing behind an observer)", bearings.source, skipped, n - 1, max_u)
    x_m, y_m = float(np.mean(fx[keep])), float(np.mean(fy[keep]))  # eq. 29
    dk = det[keep]
    return LocateResult(
        x_m=x_m, y_m=y_m, method=FixMethod.MEAN, u=float(np.max(u[keep])),
        determinant=float(dk[np.argmin(np.abs(dk))]), n_bearings=n,
        pair_rows=tuple((int(i), int(j)) for i, j in zip(rows_i[keep], rows_j[keep])),
        pair_x_m=fx[keep], pair_y_m=fy[keep], pair_u=u[keep], pair_determinant=dk,
        pairs_skipped=skipped, residual_deg=_residuals(bearings, x_m, y_m))


def locate(bearings: Bearings, *, method: FixMethod | str = FixMethod.LSQ,
           max_u: float = DEFAULT_MAX_U) -> LocateResult:
    """Estimate a stationary target's position from bearings.

    Parameters
    ----------
    bearings : Bearings
        Two or more bearings at distinct observer positions.
    method : FixMethod or str
        ``crossing`` (last two bearings, eqs. 6-8), ``lsq`` (all bearings) or ``mean``
        (mean of consecutive pairwise fixes, eq. 29).
    max_u : float
        Largest conditioning number (eq. 11) accepted.

    Returns
    -------
    LocateResult

    Raises
    ------
    LocateError
        See `crossing_fix`, `lsq_fix`, `mean_fix`.
    """
    try:
        method = FixMethod(method)
    except ValueError:
        raise LocateError(f"method: must be one of {', '.join(m.value for m in FixMethod)}, "
                          f"got {method!r}") from None
    if not (math.isfinite(max_u) and max_u >= 1.0):
        raise LocateError(f"max_u: the conditioning limit must be a finite number >= 1, "
                          f"got {max_u}")
    return {FixMethod.CROSSING: crossing_fix, FixMethod.LSQ: lsq_fix,
            FixMethod.MEAN: mean_fix}[method](bearings, max_u=max_u)
