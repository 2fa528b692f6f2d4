"""The observer's route: courses that keep the bearings well conditioned (Schmidt et al.).

The observer takes a bearing, runs a leg of length VT (eq. 13) and takes the next. Steering each
leg perpendicular to the current bearing (eq. 17) lets u (eq. 11) grow as the observer draws
away; the modified algorithm (23) steers perpendicular to the anticipated next bearing, closes
the range and keeps |P| (eq. 10) from falling (eqs. 17-23, Figs. 1-4).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tracker.errors import LocateError
from tracker.locate.bearings import Bearings
from tracker.locate.choices import DEFAULT_MAX_U, CourseRule, Side
from tracker.locate.geometry import (
    SAME_POSITION_M,
    bearing_to_deg,
    crossing_point,
    pair_conditioning,
)
from tracker.locate.regions import check_d_alpha


@dataclass(frozen=True, slots=True, kw_only=True)
class Route:
    """An observer's route of K legs and the K + 1 bearings taken at its points.

    Attributes
    ----------
    t_s : ndarray, shape (K+1,)
        Time of each bearing, s.
    obs_x_m, obs_y_m : ndarray, shape (K+1,)
        Observer position at each bearing, m.
    course_deg : ndarray, shape (K,)
        Course of the leg from point k to point k + 1, deg.
    bearing_deg : ndarray, shape (K+1,)
        Bearing taken at each point, deg (the true bearing plus the bearing error, if any).
    range_m : ndarray, shape (K+1,)
        True range from each point to the target, m.
    u, determinant : ndarray, shape (K,)
        Conditioning number (eq. 11) and |P| (eq. 10) of the bearings k and k + 1.
    fix_x_m, fix_y_m : ndarray, shape (K,)
        Crossing fix of the bearings k and k + 1 (step 6 of algorithm (23)), m.
    target_x_m, target_y_m : float
        The target (guess) the route was planned for, m.
    rule : CourseRule
        Rule of the legs after the first.
    first_leg_rule : CourseRule
        Rule of the first leg.
    side : Side
    speed_mps, leg_s : float
        Observer speed, m/s, and leg duration, s; the leg length is VT = speed_mps * leg_s.
    min_range_m : float
        Range below which algorithm (23) stops closing and circles the target.
    """

    t_s: np.ndarray
    obs_x_m: np.ndarray
    obs_y_m: np.ndarray
    course_deg: np.ndarray
    bearing_deg: np.ndarray
    range_m: np.ndarray
    u: np.ndarray
    determinant: np.ndarray
    fix_x_m: np.ndarray
    fix_y_m: np.ndarray
    target_x_m: float
    target_y_m: float
    rule: CourseRule
    first_leg_rule: CourseRule
    side: Side
    speed_mps: float
    leg_s: float
    min_range_m: float

    @property
    def leg_m(self) -> float:
        """Leg length VT, m."""
        return self.speed_mps * self.leg_s

    def bearings(self, source: str = "route") -> Bearings:
        """The route's bearings as input for `locate`."""
        return Bearings(t_s=self.t_s, obs_x_m=self.obs_x_m, obs_y_m=self.obs_y_m,
                        bearing_deg=self.bearing_deg, source=source)

    def to_frame(self):
        """One row per bearing point: the bearings CSV columns plus the leg and pair values.

        ``course_deg`` is the course of the leg leaving the point (blank on the last row);
        ``u``, ``determinant`` belong to the pair (previous point, this point) (blank on the
        first row).
        """
        import pandas as pd

        pad_end = np.append(self.course_deg, np.nan)
        pad_start = lambda v: np.insert(np.asarray(v, dtype=float), 0, np.nan)  # noqa: E731
        return pd.DataFrame({
            "t_s": self.t_s, "obs_x_m": self.obs_x_m, "obs_y_m": self.obs_y_m,
            "bearing_deg": self.bearing_deg, "course_deg": pad_end,
            "speed_mps": np.full(len(self.t_s), self.speed_mps), "range_m": self.range_m,
            "u": pad_start(self.u), "determinant": pad_start(self.determinant),
        })


def _check_plan_inputs(target_x_m, target_y_m, start_x_m, start_y_m, speed_mps, leg_s, n_legs,
                       min_range_m) -> None:
    for name, value, unit in (("target_x_m", target_x_m, "m"), ("target_y_m", target_y_m, "m"),
                              ("start_x_m", start_x_m, "m"), ("start_y_m", start_y_m, "m")):
        if not math.isfinite(value):
            raise LocateError(f"{name}: must be a finite number, got {value} {unit}")
    for name, value, unit in (("speed_mps", speed_mps, "m/s"), ("leg_s", leg_s, "s")):
        if not (math.isfinite(value) and value > 0.0):
            raise LocateError(f"{name}: must be > 0 {unit}, got {value} {unit}")
    if int(n_legs) != n_legs or not 1 <= n_legs <= 100_000:
        raise LocateError(f"n_legs: must be an integer in [1, 100000], got {n_legs}")
    if min_range_m is not None and not (math.isfinite(min_range_m) and min_range_m >= 0.0):
        raise LocateError(f"min_range_m: must be >= 0 m, got {min_range_m} m")
    if math.hypot(target_x_m - start_x_m, target_y_m - start_y_m) < SAME_POSITION_M:
        raise LocateError(f"the start position ({start_x_m:g}, {start_y_m:g}) m coincides with "
                          f"the target guess ({target_x_m:g}, {target_y_m:g}) m; no bearing")


def course_offset_deg(range_m, leg_m: float, rule: CourseRule | str,
                      min_range_m: float) -> np.ndarray:
    """Angle theta by which the course turns from perpendicular-to-the-bearing, deg.

    The course is beta = alpha +- (90 deg - theta) (+ to keep the target to port):

    - eq. 17: theta = 0, perpendicular to the current bearing;
    - eq. 23: theta = arcsin(VT / R), perpendicular to the anticipated next bearing
      alpha_{n+1} = alpha_n -+ arcsin(VT / R_n) (steps 2-3), which brings the range to
      sqrt(R^2 - VT^2) and keeps |P| (eq. 10) from falling;
    - when that next range would fall below ``min_range_m``, the leg is a chord of the circle
      of radius R about the target (theta = arcsin(VT / 2R)), which holds u constant; if even
      that is impossible (VT > 2R) the leg is perpendicular to the bearing (theta = 0).
    """
    r = np.asarray(range_m, dtype=float)
    if CourseRule(rule) is CourseRule.EQ17:
        return np.zeros_like(r)
    with np.errstate(invalid="ignore", divide="ignore"):
        closing = r ** 2 - leg_m ** 2 >= min_range_m ** 2
        theta = np.where(closing, np.arcsin(np.clip(leg_m / r, 0.0, 1.0)),
                         np.where(leg_m <= 2.0 * r,
                                  np.arcsin(np.clip(leg_m / (2.0 * r), 0.0, 1.0)), 0.0))
    return np.degrees(theta)


def plan_route(*, target_x_m: float, target_y_m: float, speed_mps: float, leg_s: float,
               n_legs: int, start_x_m: float = 0.0, start_y_m: float = 0.0,
               rule: CourseRule | str = CourseRule.EQ23, side: Side | str = Side.PORT,
               min_range_m: float | None = None, first_leg_rule: CourseRule | str | None = None,
               d_alpha_deg: float = 0.0, rng: np.random.Generator | None = None,
               max_u: float = DEFAULT_MAX_U) -> Route:
    """Plan (or simulate) the observer's route for K legs by eq. 17 or algorithm (23).

    At each point n the observer takes a bearing alpha_n and steers the next leg of length
    VT = speed_mps * leg_s (eq. 13). With rule ``eq17`` the course is perpendicular to
    alpha_n. With rule ``eq23`` it is perpendicular to the anticipated next bearing
    alpha_{n+1} = alpha_n - arcsin(VT / R_n) (steps 1-5 of algorithm (23)); R_1 is the range
    to the target guess ("R1 known"), later R_n is the range to the crossing fix of the two
    latest bearings (step 6), which equals the guess when the bearings are exact.

    Parameters
    ----------
    target_x_m, target_y_m : float
        Target position (the guess the route is planned for), m.
    speed_mps : float
        Observer speed V, m/s.
    leg_s : float
        Time T between bearings, s.
    n_legs : int
        Number of legs K; the route has K + 1 bearing points.
    start_x_m, start_y_m : float
        First bearing point, m.
    rule : CourseRule or str
        ``eq23`` (default) or ``eq17``.
    side : Side or str
        ``port`` (course = bearing + 90 deg, the paper's choice) or ``starboard``.
    first_leg_rule : CourseRule or str, optional
        Rule for the first leg only; default ``rule``. The paper's text steers the first leg
        by eq. 17 (the second bearing is not yet known) and the later ones by (23); with
        ``rule="eq23"`` and R_1 known from the guess, the first leg too follows (23), which
        is what gives the paper's Fig. 8 numbers.
    min_range_m : float, optional
        Algorithm (23) closes the range by sqrt(R^2 - VT^2) only while that stays at or above
        this range, then circles the target. Default VT / sqrt(2), at which a chord of the
        circle spans 90 deg of bearing (u = 1).
    d_alpha_deg : float
        Bound of a uniform bearing error U(-D_alpha, D_alpha) added to each bearing, deg;
        0 (default) plans with exact bearings.
    rng : numpy.random.Generator, optional
        Required when ``d_alpha_deg > 0``.
    max_u : float
        A pair with u above this gives no fix; steering then keeps the previous range.

    Returns
    -------
    Route
    """
    _check_plan_inputs(target_x_m, target_y_m, start_x_m, start_y_m, speed_mps, leg_s, n_legs,
                       min_range_m)
    try:
        rule, side = CourseRule(rule), Side(side)
        first_rule = rule if first_leg_rule is None else CourseRule(first_leg_rule)
    except ValueError as exc:
        raise LocateError(f"route: {exc}") from None
    if d_alpha_deg:
        check_d_alpha(d_alpha_deg)
        if rng is None:
            raise LocateError("route: d_alpha_deg > 0 needs a random generator (rng)")
    leg_m = speed_mps * leg_s
    r_min = leg_m / math.sqrt(2.0) if min_range_m is None else float(min_range_m)
    k = int(n_legs)
    xs, ys = np.empty(k + 1), np.empty(k + 1)
    bearing = np.empty(k + 1)
    course = np.empty(k)
    fix_x, fix_y = np.full(k, np.nan), np.full(k, np.nan)
    xs[0], ys[0] = start_x_m, start_y_m

    def take_bearing(n: int) -> None:
        true = float(bearing_to_deg(xs[n], ys[n], target_x_m, target_y_m))
        err = float(rng.uniform(-d_alpha_deg, d_alpha_deg)) if d_alpha_deg else 0.0
        bearing[n] = (true + err) % 360.0

    take_bearing(0)
    est_x, est_y = float(target_x_m), float(target_y_m)  # R1 known: the target guess
    for n in range(k):
        if n >= 1:  # step 6 of (23) for the pair (n-1, n), then step 1 uses it
            fx, fy, r1, r2, _ = crossing_point(xs[n - 1], ys[n - 1], bearing[n - 1],
                                               xs[n], ys[n], bearing[n])
            u_pair = float(pair_conditioning(bearing[n - 1] - bearing[n]))
            if u_pair <= max_u and r1 > 0.0 and r2 > 0.0:
                fix_x[n - 1], fix_y[n - 1] = float(fx), float(fy)
                est_x, est_y = float(fx), float(fy)
        r_est = math.hypot(est_x - xs[n], est_y - ys[n])
        theta = float(course_offset_deg(r_est, leg_m, first_rule if n == 0 else rule, r_min))
        course[n] = (bearing[n] + side.sign * (90.0 - theta)) % 360.0  # eqs. 17, 23 step 3
        c = math.radians(course[n])
        xs[n + 1] = xs[n] + leg_m * math.sin(c)  # eq. 13
        ys[n + 1] = ys[n] + leg_m * math.cos(c)
        take_bearing(n + 1)
    fx, fy, r1, r2, det = crossing_point(xs[-2], ys[-2], bearing[-2], xs[-1], ys[-1], bearing[-1])
    if float(pair_conditioning(bearing[-2] - bearing[-1])) <= max_u and r1 > 0.0 and r2 > 0.0:
        fix_x[-1], fix_y[-1] = float(fx), float(fy)
    delta = bearing[:-1] - bearing[1:]
    return Route(
        t_s=np.arange(k + 1) * float(leg_s), obs_x_m=xs, obs_y_m=ys, course_deg=course,
        bearing_deg=bearing, range_m=np.hypot(target_x_m - xs, target_y_m - ys),
        u=pair_conditioning(delta), determinant=np.sin(np.radians(delta)),
        fix_x_m=fix_x, fix_y_m=fix_y, target_x_m=float(target_x_m),
        target_y_m=float(target_y_m), rule=rule, first_leg_rule=first_rule, side=side,
        speed_mps=float(speed_mps), leg_s=float(leg_s), min_range_m=r_min)


def conditioning_vs_course(alpha1_deg: float, leg_over_range: float, course_deg) -> np.ndarray:
    """u (eq. 11) of the first two bearings as a function of the first leg's course (Fig. 1).

    The observer starts at the origin with the target at unit range on bearing ``alpha1_deg``
    and runs a leg of length VT / R_1 = ``leg_over_range`` on each course beta_1 (eq. 13).

    Parameters
    ----------
    alpha1_deg : float
        First bearing, deg.
    leg_over_range : float
        VT / R_1, > 0.
    course_deg : array_like
        Courses beta_1, deg.

    Returns
    -------
    u : ndarray
        Conditioning number for each course (``inf`` where the leg runs along the bearing).
    """
    a1 = math.radians(alpha1_deg)
    b = np.radians(np.asarray(course_deg, dtype=float))
    x2, y2 = leg_over_range * np.sin(b), leg_over_range * np.cos(b)
    a2 = bearing_to_deg(x2, y2, math.sin(a1), math.cos(a1))
    return pair_conditioning(alpha1_deg - a2)
