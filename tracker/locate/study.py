"""A fix from bearings with its error region and Monte Carlo (what ``tmakit locate`` reports), and
a route planned toward a target guess with what it promises: per-leg error-region diagonals, the
error region of its first pair of bearings (the paper's Fig. 8) and a Monte Carlo of its first leg
(Fig. 9) (what ``tmakit locate plan`` reports and draws).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from tracker.errors import LocateError
from tracker.locate.bearings import Bearings
from tracker.locate.choices import FixMethod
from tracker.locate.fixes import locate
from tracker.locate.montecarlo import monte_carlo_first_leg, monte_carlo_locate
from tracker.locate.regions import error_polygon, error_region
from tracker.locate.route import plan_route


@dataclass(frozen=True, slots=True, kw_only=True)
class MonteCarloSummary:
    """The first leg's Monte Carlo fixes at a glance: trials, fixes made, their mean, and the
    fraction inside the planned error region (None without a region or without fixes)."""

    trials: int
    fixes: int
    mean_x_m: float | None
    mean_y_m: float | None
    inside_fraction: float | None


@dataclass(frozen=True, slots=True, kw_only=True)
class RoutePlan:
    """A planned route and what it promises.

    Attributes
    ----------
    route : Route
        The route (simulated bearings when asked).
    table : pandas.DataFrame
        The route's rows (``Route.to_frame``) with ``d13_m``, ``d24_m``, ``area_m2`` of the error
        region of each leg's pair of bearings (NaN on the first row, and where none exists).
    region : ErrorRegion or PolygonRegion or None
        The error region of the exact route's first pair of bearings; None when it has none.
    region_problem : str or None
        Why there is no region.
    monte_carlo : MonteCarlo or None
        The first leg's Monte Carlo (None for no trials).
    monte_carlo_summary : MonteCarloSummary or None
    """

    route: object
    table: pd.DataFrame
    region: object | None
    region_problem: str | None
    monte_carlo: object | None
    monte_carlo_summary: MonteCarloSummary | None


def plan_study(*, target_x_m: float, target_y_m: float, start_x_m: float, start_y_m: float,
               speed_mps: float, leg_s: float, n_legs: int, rule, side, min_range_m: float,
               first_leg_rule, d_alpha_deg: float, simulate: bool, n_trials: int,
               rng: np.random.Generator) -> RoutePlan:
    """Plan the route (``plan_route``; with ``simulate`` its bearings carry uniform errors within
    +-``d_alpha_deg``), and evaluate it: the error regions of its legs, the region of the exact
    route's first pair, and ``n_trials`` Monte Carlo trials of the first leg."""
    if not (math.isfinite(d_alpha_deg) and 0.0 < d_alpha_deg < 45.0):
        raise LocateError(f"bearing error bound D_alpha: must be in (0, 45) deg, got {d_alpha_deg} deg")
    if not 0 <= n_trials <= 10_000_000:
        raise LocateError(f"Monte Carlo trials: must be in [0, 10000000], got {n_trials}")
    common = dict(target_x_m=target_x_m, target_y_m=target_y_m, start_x_m=start_x_m,
                  start_y_m=start_y_m, speed_mps=speed_mps, leg_s=leg_s, rule=rule, side=side,
                  min_range_m=min_range_m, first_leg_rule=first_leg_rule)
    route = plan_route(**common, n_legs=n_legs, d_alpha_deg=d_alpha_deg if simulate else 0.0,
                       rng=rng if simulate else None)
    exact = plan_route(**common, n_legs=1)
    region, region_problem = None, None
    try:  # the first pair of the planned (exact) route, as in the paper's Fig. 8
        region = error_region(exact.obs_x_m, exact.obs_y_m, target_x_m, target_y_m, d_alpha_deg=d_alpha_deg)
    except LocateError as exc:
        region_problem = str(exc)
    mc = None
    if n_trials:
        mc = monte_carlo_first_leg(target_x_m=target_x_m, target_y_m=target_y_m, leg_m=route.leg_m,
                                   d_alpha_deg=d_alpha_deg, n_trials=n_trials, rng=rng,
                                   start_x_m=start_x_m, start_y_m=start_y_m,
                                   rule=first_leg_rule or rule, side=side, min_range_m=min_range_m)
    table = route.to_frame()
    d13, d24, area = [math.nan], [math.nan], [math.nan]
    for k in range(1, len(route.t_s)):
        try:
            r = error_region(route.obs_x_m[k - 1:k + 1], route.obs_y_m[k - 1:k + 1], target_x_m,
                             target_y_m, d_alpha_deg=d_alpha_deg)
            d13.append(r.d13_m), d24.append(r.d24_m), area.append(r.area_m2)
        except LocateError:
            d13.append(math.nan), d24.append(math.nan), area.append(math.nan)
    table["d13_m"], table["d24_m"], table["area_m2"] = d13, d24, area
    return RoutePlan(route=route, table=table, region=region, region_problem=region_problem,
                     monte_carlo=mc, monte_carlo_summary=summarize_monte_carlo(mc, region))


def summarize_monte_carlo(mc, region) -> MonteCarloSummary | None:
    """`MonteCarloSummary` of Monte Carlo fixes against an error region (either may be None)."""
    if mc is None:
        return None
    found = mc.x_m.size > 0
    inside = (float(np.mean(region.contains(mc.x_m, mc.y_m, tol_m=1e-6)))
              if region is not None and found else None)
    return MonteCarloSummary(trials=mc.n_trials, fixes=int(mc.x_m.size),
                             mean_x_m=mc.mean_x_m if found else None,
                             mean_y_m=mc.mean_y_m if found else None, inside_fraction=inside)


@dataclass(frozen=True, slots=True, kw_only=True)
class LocateStudy:
    """A fix and what its bearings' error bound allows.

    Attributes
    ----------
    result : LocateResult
    region : ErrorRegion or PolygonRegion or None
        Two bearings (or the crossing method): the quadrilateral of the last two; more: the
        intersection of every bearing's wedge. None when it has none.
    region_note : str
        Which region it is, for a report.
    region_problem : str or None
        Why there is no region.
    monte_carlo : MonteCarlo or None
    monte_carlo_summary : MonteCarloSummary or None
    """

    result: object
    region: object | None
    region_note: str
    region_problem: str | None
    monte_carlo: object | None
    monte_carlo_summary: MonteCarloSummary | None


def locate_study(bearings: Bearings, *, method, max_u: float, d_alpha_deg: float, n_trials: int,
                 rng: np.random.Generator) -> LocateStudy:
    """Locate the target (``locate``), its error region for bearing errors within
    +-``d_alpha_deg`` and ``n_trials`` Monte Carlo trials of the same fix."""
    result = locate(bearings, method=method, max_u=max_u)
    n = len(bearings)
    region, region_note, region_problem = None, "", None
    try:
        if n == 2 or result.method is FixMethod.CROSSING:
            region_note = f"quadrilateral of rows {n - 1} and {n}"
            region = error_region(bearings.obs_x_m[-2:], bearings.obs_y_m[-2:], result.x_m,
                                  result.y_m, d_alpha_deg=d_alpha_deg)
        else:
            region_note = f"intersection of the {n} bearing wedges"
            region = error_polygon(bearings.obs_x_m, bearings.obs_y_m, result.x_m, result.y_m,
                                   d_alpha_deg=d_alpha_deg)
    except LocateError as exc:
        region_problem = str(exc)
    mc = None
    if n_trials:
        mc = monte_carlo_locate(bearings, result.x_m, result.y_m, d_alpha_deg=d_alpha_deg,
                                n_trials=n_trials, rng=rng, method=result.method, max_u=max_u)
    return LocateStudy(result=result, region=region, region_note=region_note,
                       region_problem=region_problem, monte_carlo=mc,
                       monte_carlo_summary=summarize_monte_carlo(mc, region))
