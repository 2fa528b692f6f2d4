"""Fixes from bearings with uniform errors in [-D_alpha, D_alpha] (Schmidt et al., Figs. 5, 6, 9).

`monte_carlo_first_leg` repeats the paper's numerical experiment on the first pair of bearings
of a planned route; `monte_carlo_locate` perturbs given bearings and applies a fix method to each
trial. The mean of the trial fixes is eq. 29.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tracker.errors import LocateError
from tracker.locate.bearings import Bearings
from tracker.locate.choices import DEFAULT_MAX_U, CourseRule, FixMethod, Side
from tracker.locate.geometry import (
    bearing_to_deg,
    crossing_point,
    pair_conditioning,
)
from tracker.locate.regions import check_d_alpha
from tracker.locate.route import course_offset_deg


@dataclass(frozen=True, slots=True, kw_only=True)
class MonteCarlo:
    """Fixes from bearings with uniform errors in [-D_alpha, D_alpha].

    Attributes
    ----------
    x_m, y_m : ndarray
        One fix per trial, m (trials with no fix are dropped).
    obs2_x_m, obs2_y_m : ndarray
        Second observer position of each trial (moves with the first bearing's error when the
        first leg is steered on the measured bearing), m; empty for `monte_carlo_locate`.
    n_trials : int
        Trials run.
    d_alpha_deg : float
    """

    x_m: np.ndarray
    y_m: np.ndarray
    obs2_x_m: np.ndarray
    obs2_y_m: np.ndarray
    n_trials: int
    d_alpha_deg: float

    @property
    def mean_x_m(self) -> float:
        """Mean fix, eq. 29, m."""
        return float(np.mean(self.x_m))

    @property
    def mean_y_m(self) -> float:
        """Mean fix, eq. 29, m."""
        return float(np.mean(self.y_m))


def monte_carlo_first_leg(*, target_x_m: float, target_y_m: float, leg_m: float,
                          d_alpha_deg: float, n_trials: int, rng: np.random.Generator,
                          start_x_m: float = 0.0, start_y_m: float = 0.0,
                          rule: CourseRule | str = CourseRule.EQ23,
                          side: Side | str = Side.PORT, min_range_m: float | None = None,
                          steer_on_measured: bool = True) -> MonteCarlo:
    """The paper's numerical experiment (Figs. 5, 6, 9): first-pair fixes with bearing errors.

    Each trial takes the first bearing with a uniform error dalpha_1 in [-D_alpha, D_alpha],
    runs one leg of length VT by ``rule`` (R_1 known), takes the second bearing with its own
    error dalpha_2 and crosses the two lines (eq. 24).

    Parameters
    ----------
    target_x_m, target_y_m : float
        True target position, m.
    leg_m : float
        Leg length VT, m.
    d_alpha_deg : float
        Bearing error bound, deg.
    n_trials : int
        Number of trials (the paper: 1000).
    rng : numpy.random.Generator
    start_x_m, start_y_m : float
        First bearing point, m.
    rule, side, min_range_m
        As in `plan_route` (for the first leg).
    steer_on_measured : bool
        True (default, as in the paper): the first leg's course follows the measured first
        bearing, so the second point moves with the first error ("the second bearing is taken
        at different points depending on the current bearing error"). False: the second point
        is the planned one, and every fix then lies in the `ErrorRegion` quadrilateral.

    Returns
    -------
    MonteCarlo
    """
    check_d_alpha(d_alpha_deg)
    if int(n_trials) != n_trials or n_trials < 1:
        raise LocateError(f"n_trials: must be an integer >= 1, got {n_trials}")
    rule, side = CourseRule(rule), Side(side)
    alpha1 = float(bearing_to_deg(start_x_m, start_y_m, target_x_m, target_y_m))
    r1 = math.hypot(target_x_m - start_x_m, target_y_m - start_y_m)
    e1 = rng.uniform(-d_alpha_deg, d_alpha_deg, int(n_trials))
    e2 = rng.uniform(-d_alpha_deg, d_alpha_deg, int(n_trials))
    measured1 = alpha1 + e1
    r_min = leg_m / math.sqrt(2.0) if min_range_m is None else float(min_range_m)
    theta = float(course_offset_deg(r1, leg_m, rule, r_min))
    steer = measured1 if steer_on_measured else np.full(int(n_trials), alpha1)
    course = np.radians(steer + side.sign * (90.0 - theta))
    x2 = start_x_m + leg_m * np.sin(course)
    y2 = start_y_m + leg_m * np.cos(course)
    measured2 = bearing_to_deg(x2, y2, target_x_m, target_y_m) + e2
    fx, fy, ra, rb, _ = crossing_point(start_x_m, start_y_m, measured1, x2, y2, measured2)
    ok = np.isfinite(fx) & (ra > 0.0) & (rb > 0.0)
    return MonteCarlo(x_m=fx[ok], y_m=fy[ok], obs2_x_m=x2, obs2_y_m=y2, n_trials=int(n_trials),
                      d_alpha_deg=float(d_alpha_deg))


def monte_carlo_locate(bearings: Bearings, x_m: float, y_m: float, *, d_alpha_deg: float,
                       n_trials: int, rng: np.random.Generator,
                       method: FixMethod | str = FixMethod.LSQ,
                       max_u: float = DEFAULT_MAX_U) -> MonteCarlo:
    """Fixes from the bearings seen at (x_m, y_m) plus uniform errors in [-D_alpha, D_alpha].

    The observer positions are those of ``bearings``; each trial perturbs every exact bearing
    independently and applies ``method`` (vectorised over the trials). Trials whose fix is
    ill-conditioned or crosses behind an observer are dropped.
    """
    check_d_alpha(d_alpha_deg)
    if int(n_trials) != n_trials or n_trials < 1:
        raise LocateError(f"n_trials: must be an integer >= 1, got {n_trials}")
    method = FixMethod(method)
    ox, oy = bearings.obs_x_m, bearings.obs_y_m
    exact = bearing_to_deg(ox, oy, x_m, y_m)
    a = exact[None, :] + rng.uniform(-d_alpha_deg, d_alpha_deg, (int(n_trials), len(ox)))
    if method is FixMethod.LSQ:
        ar = np.radians(a)
        c, s = np.cos(ar), np.sin(ar)
        xr, yr = float(np.mean(ox)), float(np.mean(oy))
        b = c * (ox - xr) - s * (oy - yr)
        # normal equations of P x = b with rows (c, -s), per trial
        pcc, pss, pcs = np.sum(c * c, 1), np.sum(s * s, 1), -np.sum(c * s, 1)
        qc, qs = np.sum(c * b, 1), -np.sum(s * b, 1)
        det = pcc * pss - pcs ** 2
        tr = pcc + pss
        disc = np.sqrt(np.maximum(tr ** 2 / 4.0 - det, 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            u = np.sqrt((tr / 2.0 + disc) / (tr / 2.0 - disc))
            fx = (pss * qc - pcs * qs) / det + xr
            fy = (pcc * qs - pcs * qc) / det + yr
        ok = u <= max_u
    else:
        if method is FixMethod.CROSSING:
            i, j = np.array([len(ox) - 2]), np.array([len(ox) - 1])
        else:
            i, j = np.arange(len(ox) - 1), np.arange(1, len(ox))
        px, py, r1, r2, _ = crossing_point(ox[i], oy[i], a[:, i], ox[j], oy[j], a[:, j])
        good = (pair_conditioning(a[:, i] - a[:, j]) <= max_u) & (r1 > 0.0) & (r2 > 0.0)
        count = np.sum(good, 1)
        with np.errstate(invalid="ignore", divide="ignore"):
            fx = np.sum(np.where(good, px, 0.0), 1) / count
            fy = np.sum(np.where(good, py, 0.0), 1) / count
        ok = count > 0
    return MonteCarlo(x_m=fx[ok], y_m=fy[ok], obs2_x_m=np.empty(0), obs2_y_m=np.empty(0),
                      n_trials=int(n_trials), d_alpha_deg=float(d_alpha_deg))
