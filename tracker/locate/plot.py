"""Plots for stationary target location: analogues of Schmidt et al.'s Figs. 1, 3, 4, 8 and 9.

Figures come from `acoustics.plots.figures.new_figure` (the Agg canvas, no pyplot state); write them
with `acoustics.plots.figures.save_figure`.
"""

from __future__ import annotations

import math

import numpy as np
from matplotlib.figure import Figure

from acoustics.plots.figures import new_figure
from tracker.locate.bearings import Bearings
from tracker.locate.fixes import LocateResult
from tracker.locate.geometry import pair_conditioning
from tracker.locate.montecarlo import MonteCarlo
from tracker.locate.regions import ErrorPolygon, ErrorRegion
from tracker.locate.route import Route, conditioning_vs_course

#: VT / R1 values drawn in the Fig. 1 analogue (the route's own value is added).
FIG1_LEG_OVER_RANGE = (0.05, 0.1, 0.2, 0.3)


def _closed(vertices: np.ndarray) -> np.ndarray:
    return np.vstack([vertices, vertices[:1]])


def _bearing_lines(ax, obs_x, obs_y, bearing_deg, length_m, **style) -> None:
    a = np.radians(bearing_deg)
    for x, y, ak in zip(obs_x, obs_y, a):
        ax.plot([x, x + length_m * math.sin(ak)], [y, y + length_m * math.cos(ak)], **style)


def _wedge_lines(ax, obs_x, obs_y, x_m, y_m, d_alpha_deg, length_scale=1.6) -> None:
    for x, y in zip(obs_x, obs_y):
        a = math.degrees(math.atan2(x_m - x, y_m - y))
        r = length_scale * math.hypot(x_m - x, y_m - y)
        for e in (-d_alpha_deg, d_alpha_deg):
            _bearing_lines(ax, [x], [y], [a + e], r, color="0.6", lw=0.7, ls="--")


def _draw_region(ax, region, label: str) -> None:
    v = _closed(region.vertices_m)
    ax.plot(v[:, 0], v[:, 1], color="tab:red", lw=1.2, label=label)
    if isinstance(region, ErrorRegion):
        for k, (vx, vy) in enumerate(region.vertices_m, start=1):
            ax.annotate(str(k), (vx, vy), textcoords="offset points", xytext=(3, 3), fontsize=8,
                        color="tab:red")
        ax.plot(*region.vertices_m[[0, 2]].T, color="tab:red", lw=0.6, ls=":")
        ax.plot(*region.vertices_m[[1, 3]].T, color="tab:red", lw=0.6, ls=":")


def _region_title(region) -> str:
    if isinstance(region, ErrorRegion):
        return (f"D_alpha = {region.d_alpha_deg:g} deg: d13 = {region.d13_m:.4g} m, "
                f"d24 = {region.d24_m:.4g} m, area = {region.area_m2:.4g} m$^2$")
    return (f"D_alpha = {region.d_alpha_deg:g} deg: area = {region.area_m2:.4g} m$^2$, "
            f"diameter = {region.diameter_m:.4g} m")


def _fig8(ax, obs_x, obs_y, x_m, y_m, region, bearing_deg=None) -> None:
    """Fig. 8 analogue: observer points, bearing lines and the error quadrilateral."""
    ax.plot(obs_x, obs_y, "+", color="tab:blue", ms=8, label="observer")
    if bearing_deg is not None:
        reach = 1.3 * float(np.max(np.hypot(x_m - np.asarray(obs_x), y_m - np.asarray(obs_y))))
        _bearing_lines(ax, obs_x, obs_y, bearing_deg, reach, color="tab:blue", lw=0.6, alpha=0.6)
    if region is not None:
        if isinstance(region, ErrorRegion):  # the extreme bearing lines of the pair (Fig. 7)
            _wedge_lines(ax, obs_x[-2:], obs_y[-2:], x_m, y_m, region.d_alpha_deg)
        _draw_region(ax, region, "error region")
        ax.set_title(_region_title(region), fontsize=8)
    ax.plot([x_m], [y_m], "x", color="k", ms=8, label="target / estimate")
    ax.set_xlabel("x east, m")
    ax.set_ylabel("y north, m")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize=7, loc="best")


def _fig9(ax, x_m, y_m, region, mc: MonteCarlo | None) -> None:
    """Fig. 9 analogue: the error region magnified with Monte Carlo fixes."""
    if mc is not None and mc.x_m.size:
        ax.plot(mc.x_m, mc.y_m, ".", ms=2, color="tab:green", alpha=0.6,
                label=f"{mc.x_m.size} trial fixes")
        ax.plot([mc.mean_x_m], [mc.mean_y_m], "o", mfc="none", color="tab:purple", ms=8,
                label=f"mean (eq. 29) ({mc.mean_x_m:.1f}, {mc.mean_y_m:.1f}) m")
    if region is not None:
        _draw_region(ax, region, "error region")
    ax.plot([x_m], [y_m], "x", color="k", ms=8, label="target / estimate")
    ax.set_title("magnified, uniform bearing errors", fontsize=8)
    ax.set_xlabel("x east, m")
    ax.set_ylabel("y north, m")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize=7, loc="best")


def _fig4(ax, u, determinant, first_index: int = 2) -> None:
    """Fig. 4 analogue: u and 1/|P| of consecutive bearing pairs."""
    k = np.arange(first_index, first_index + len(u))
    ax.plot(k, u, "o-", ms=3, label="u (eq. 11)")
    with np.errstate(divide="ignore"):
        ax.plot(k, 1.0 / np.abs(determinant), "s--", ms=3, label="1/|P| (eq. 10)")
    ax.set_xlabel("bearing number n (pair n-1, n)")
    ax.set_ylabel("u, 1/|P|")
    ax.set_ylim(bottom=0.0)
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=7)
    ax.set_title("conditioning of consecutive bearing pairs", fontsize=8)


def locate_figure(bearings: Bearings, result: LocateResult,
                  region: ErrorRegion | ErrorPolygon | None,
                  mc: MonteCarlo | None) -> Figure:
    """Figure for a fix: geometry and error region (Fig. 8), magnified with trials (Fig. 9),
    and, for more than two bearings, u and 1/|P| of consecutive pairs (Fig. 4)."""
    n_panels = 3 if len(bearings) > 2 else 2
    fig = new_figure(figsize=(5.0 * n_panels, 4.8), layout="constrained")
    axes = fig.subplots(1, n_panels)
    _fig8(axes[0], bearings.obs_x_m, bearings.obs_y_m, result.x_m, result.y_m, region,
          bearings.bearing_deg)
    _fig9(axes[1], result.x_m, result.y_m, region, mc)
    if n_panels == 3:
        delta = bearings.bearing_deg[:-1] - bearings.bearing_deg[1:]
        _fig4(axes[2], pair_conditioning(delta), np.sin(np.radians(delta)))
    fig.suptitle(f"{bearings.source}: {result.method.value} fix ({result.x_m:.1f}, "
                 f"{result.y_m:.1f}) m, u = {result.u:.3g}", fontsize=10)
    return fig


def plan_figure(route: Route, region: ErrorRegion | None, mc: MonteCarlo | None) -> Figure:
    """Figure for a planned route: Figs. 1, 3, 4, 8 and 9 of the paper."""
    fig = new_figure(figsize=(15.0, 9.0), layout="constrained")
    axes = fig.subplots(2, 3).ravel()
    # Fig. 1: u against the first leg's course for several VT/R1
    alpha1 = float(route.bearing_deg[0])
    ratio = route.leg_m / float(route.range_m[0])
    course = np.arange(0.0, 360.0, 0.5)
    ax = axes[0]
    for q in sorted(set(FIG1_LEG_OVER_RANGE) | {round(ratio, 3)}):
        ax.plot(course, conditioning_vs_course(alpha1, q, course), lw=1.5 if q == round(
            ratio, 3) else 0.8, label=f"VT/R1 = {q:g}")
    ax.axvline(route.course_deg[0], color="k", lw=0.6, ls=":", label="first course")
    ax.set_yscale("log")
    ax.set_ylim(1.0, 1e3)
    ax.set_xlabel("course beta1, deg")
    ax.set_ylabel("u")
    ax.set_title(f"Fig. 1: u against course, alpha1 = {alpha1:.1f} deg", fontsize=8)
    ax.legend(fontsize=7)
    # Fig. 3: the route
    ax = axes[1]
    ax.plot(route.obs_x_m, route.obs_y_m, "+-", color="tab:blue", lw=0.6, ms=7, label="route")
    ax.plot([route.target_x_m], [route.target_y_m], "x", color="k", ms=9, label="target")
    phi = np.linspace(0.0, 2.0 * math.pi, 361)
    r1 = float(route.range_m[0])
    ax.plot(route.target_x_m + r1 * np.sin(phi), route.target_y_m + r1 * np.cos(phi),
            color="0.6", lw=0.6, label="range R1")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x east, m")
    ax.set_ylabel("y north, m")
    ax.set_title(f"Fig. 3: route, rule {route.rule.value}, {len(route.course_deg)} legs of "
                 f"{route.leg_m:.4g} m", fontsize=8)
    ax.legend(fontsize=7)
    # Fig. 4: u and 1/|P| along the route
    _fig4(axes[2], route.u, route.determinant)
    axes[2].set_title("Fig. 4: " + axes[2].get_title(), fontsize=8)
    # Fig. 8 and Fig. 9: first pair's error region and the Monte Carlo
    _fig8(axes[3], route.obs_x_m[:2], route.obs_y_m[:2], route.target_x_m, route.target_y_m,
          region, route.bearing_deg[:2])
    axes[3].set_title("Fig. 8: " + axes[3].get_title(), fontsize=8)
    _fig9(axes[4], route.target_x_m, route.target_y_m, region, mc)
    axes[4].set_title("Fig. 9: " + axes[4].get_title(), fontsize=8)
    axes[5].set_axis_off()
    lines = [f"rule {route.rule.value}, side {route.side.value}",
             f"speed {route.speed_mps:g} m/s, leg {route.leg_s:g} s (VT = {route.leg_m:.4g} m)",
             f"first u = {route.u[0]:.4g}, last u = {route.u[-1]:.4g}"]
    if region is not None:
        lines += [f"d13 = {region.d13_m:.4g} m (eq. 25: {region.d13_eq25_m:.4g} m)",
                  f"d24 = {region.d24_m:.4g} m (eq. 27: {region.d24_eq27_m:.4g} m)",
                  f"d24/d13 = {region.ratio:.4g} (eq. 28: {region.ratio_eq28:.4g})",
                  f"area = {region.area_m2:.4g} m^2"]
    if mc is not None and mc.x_m.size:
        lines.append(f"mean of {mc.x_m.size} fixes: ({mc.mean_x_m:.1f}, {mc.mean_y_m:.1f}) m")
    axes[5].text(0.0, 1.0, "\n".join(lines), va="top", fontsize=9, family="monospace")
    return fig
