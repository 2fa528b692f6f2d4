"""The probability of detection drawn: a map around a bearing-dependent grid's origin, or P_D
against range for a grid without bearings.

``tmakit grids plot FILE --what pd [--band NAME|any]``. P_D = Phi(SE / sigma) of each class in one
band or any band (``acoustics.grid.pdmap``):

- a bearing-dependent grid: one polar panel per class (north up, bearings clockwise, range in km)
  with P_D as colour (between radials linear in bearing, as the trackers take K; blank where there
  is no K: the class deeper than the water, or beyond land), the ranges
  where P_D falls through 0.9, 0.5 and 0.1 on every bearing as lines, and "beyond the table" in
  its own colour: an arc outside the outer circle on the bearings where P_D still reaches a level
  at the table's last range (no range is drawn there); land, depth contours and radials as on
  the grid's other maps (``acoustics.plots.mapplot``), and with the bathymetry file at hand the
  latitude-longitude panel with each class's 0.5 outline;
- a grid without bearings: one panel per class, P_D against range for every band and any band,
  the three levels' ranges marked, and "beyond the table" where P_D still reaches 0.1 at its end.

Artists carry ``gid``s: ``pd:CLASS`` (the P_D mesh), ``pd:CLASS:LEVEL`` (the level's range line:
bearing in radians, range in km, closed), ``beyond:CLASS:LEVEL`` (the arc), and on the flat
figure ``pd:CLASS:ROW`` (the curve: range in km, P_D).
"""

from __future__ import annotations

import math
import textwrap

import numpy as np
from matplotlib.figure import Figure

from acoustics.grid.detectionsigma import SigmaOverride
from acoustics.grid.face import Tables
from acoustics.grid.pdmap import ANY_BAND, PDMap, check_band, pd_map
from acoustics.grid.radialtables import RadialTables
from acoustics.pd import PD_LEVELS
from acoustics.plots.figures import new_figure
from acoustics.plots.mapplot import latlon_panel, map_bearings, polar_setting
from acoustics.plots.style import band_label, check_plot_options, class_label, origin_label
from envdata.bathymetry import ElevationGrid

#: "Beyond the table": P_D still reaches a level at the table's last range (never a range).
BEYOND_COLOR = "#e7298a"
#: How each level's range is drawn.
LEVEL_STYLE = {0.9: dict(ls="-", lw=1.6), 0.5: dict(ls="--", lw=1.6), 0.1: dict(ls=":", lw=1.8)}
#: The P_D colours.
PD_CMAP = "cividis"


def row_label(tables: Tables, row: str) -> str:
    return "any band" if row == ANY_BAND else f"band {band_label(tables, row)}"


def pd_map_figure(tables: RadialTables, *, band: str | None = None, classes: list[str] | None = None,
                  override: SigmaOverride | None = None, bathymetry: ElevationGrid | None = None,
                  bathymetry_note: str = "") -> tuple[Figure, dict[str, PDMap]]:
    """The P_D map around the origin (module docstring) and the P_D maps drawn, by class.

    The P_D maps are those of the radials' own bearings (the summary's); the figure evaluates
    every degree as well.
    """
    row = check_band(tables, band)
    classes = list(tables.class_names) if classes is None else list(classes)
    for c in classes:
        check_plot_options(tables, cls_name=c)
    bearings = map_bearings(tables.bearing_deg)
    r_km = tables.range_m / 1000.0
    n_panels = len(classes) + (bathymetry is not None)
    ncols = n_panels if n_panels <= 3 else math.ceil(n_panels / 2)
    nrows = math.ceil(n_panels / ncols)
    fig = new_figure(figsize=(4.7 * ncols + 0.4, 5.4 * nrows + 1.4), layout="constrained")
    axes = [fig.add_subplot(nrows, ncols, i + 1, projection="polar") for i in range(len(classes))]
    outlines, summaries, mesh = {}, {}, None
    for ax, c in zip(axes, classes):
        pm, mesh = pd_panel(ax, tables, c, row, override=override)
        outlines[c] = pm.ranges_m[0.5][pm.row(row)]
        summaries[c] = pd_map(tables, c, tables.bearing_deg, override=override)
        ax.set_title(f"class {class_label(tables, c)}, {pm.terms.level_label}, {sigma_text(pm)}\n"
                     f"{_span(pm, pm.row(row))}", fontsize=9)
    fig.colorbar(mesh, ax=axes, orientation="horizontal", shrink=0.6, aspect=45, pad=0.02,
                 label=f"P_D in {row_label(tables, row)}, one look of {pm.terms.integration_time_s:g} s")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=3, fontsize=7.5,
               title="range where P_D falls through each level; beyond the table (outside the outer circle, "
                     f"{r_km[-1]:g} km): P_D still reaches the level at the table's last range, no range",
               title_fontsize=7.5)
    title = (f"Probability of detection P_D = \u03a6(SE / \u03c3), {row_label(tables, row)}, the target at "
             f"its class's mean level\n\u03c3: {pm.sigma.source}; SE = K(r) - K needed for "
             f"Q \u2265 {pm.terms.threshold:g}\narea {tables.area_name}, origin {origin_label(tables)}, "
             f"observer at {tables.observer_depth_m:g} m; bearing clockwise from true north; tan: land\n"
             f"{tables.sonar_label()}")
    # a line as wide as the figure at most (the sigma's source is long)
    width = int(fig.get_figwidth() * 72 / (0.55 * 9))
    fig.suptitle("\n".join(textwrap.fill(line, width) for line in title.split("\n")), fontsize=9)
    if bathymetry is not None:
        ax = fig.add_subplot(nrows, ncols, len(classes) + 1)
        latlon_panel(tables, ax, bathymetry, outlines, bearings, bathymetry_note, gaps=True,
                     said="P_D = 0.5 out to (gaps: beyond the table)")
    return fig, summaries


def pd_panel(ax, tables: RadialTables, cls_name: str, row: str, *, override: SigmaOverride | None = None):
    """One class's P_D map on a polar axes (module docstring): returns its P_D map (every degree
    and radial) and the mesh (for a colour bar)."""
    from matplotlib.patheffects import Normal, Stroke

    bearings = map_bearings(tables.bearing_deg)
    closed = np.radians(np.append(bearings, bearings[0] + 360.0))
    r_km = tables.range_m / 1000.0
    pm = pd_map(tables, cls_name, bearings, override=override)
    ir = pm.row(row)
    shown = np.where(np.isnan(pm.excess_db).all(axis=1), np.nan, pm.pd[:, ir, :])   # blank: no K
    mesh = ax.pcolormesh(np.radians(bearings), r_km, shown.T, shading="nearest", cmap=PD_CMAP, vmin=0.0,
                         vmax=1.0, zorder=0, rasterized=True)
    mesh.set_gid(f"pd:{cls_name}")
    polar_setting(tables, ax, bearings, tables.bottom_at(bearings), r_km)
    ax.set_rlim(0.0, 1.09 * r_km[-1])
    for j, level in enumerate(PD_LEVELS):
        rr = pm.ranges_m[level][ir] / 1000.0
        line, = ax.plot(closed, np.append(rr, rr[0]), color="k", zorder=5, label=f"P_D = {level:g}",
                        path_effects=[Stroke(linewidth=3.2, foreground="white"), Normal()], **LEVEL_STYLE[level])
        line.set_gid(f"pd:{cls_name}:{level:g}")
        past = np.where(pm.beyond[level][ir], 1.0, np.nan) * r_km[-1] * (1.025 + 0.025 * j)
        arc, = ax.plot(closed, np.append(past, past[0]), color=BEYOND_COLOR, zorder=6, solid_capstyle="butt",
                       label=f"P_D \u2265 {level:g} at the table's last range", **{**LEVEL_STYLE[level], "lw": 3.0})
        arc.set_gid(f"beyond:{cls_name}:{level:g}")
    return pm, mesh


def sigma_text(pm: PDMap) -> str:
    """The class's sigma over bands, bearings and ranges, for a title: one value or its span."""
    total = pm.sigma.total_db
    lo, hi = float(np.min(total)), float(np.max(total))
    return f"\u03c3 {lo:.1f} dB" if hi - lo < 0.05 else f"\u03c3 {lo:.1f}-{hi:.1f} dB"


def _span(pm: PDMap, ir: int) -> str:
    """The 0.5 range over the bearings, or how many bearings pass the table's end, for a title."""
    r50 = pm.ranges_m[0.5][ir]
    past = int(pm.beyond[0.1][ir].sum())
    found = r50[np.isfinite(r50)] / 1000.0
    text = (f"P_D = 0.5 at {found.min():.1f}-{found.max():.1f} km" if found.size else "P_D = 0.5 at no range")
    if past:
        text += f"; beyond the table on {100.0 * past / pm.bearing_deg.size:.0f} % of bearings"
    return text


def pd_curves_figure(tables: Tables, *, classes: list[str] | None = None,
                     override: SigmaOverride | None = None) -> tuple[Figure, dict[str, PDMap]]:
    """P_D against range per class, every band and any band (a grid without bearings)."""
    import matplotlib

    classes = list(tables.class_names) if classes is None else list(classes)
    for c in classes:
        check_plot_options(tables, cls_name=c)
    r_km = tables.range_m / 1000.0
    fig = new_figure(figsize=(5.0 * len(classes) + 0.5, 4.6), layout="constrained")
    axes = [fig.add_subplot(1, len(classes), i + 1) for i in range(len(classes))]
    colors = matplotlib.colormaps["tab10"]
    summaries = {}
    for ax, c in zip(axes, classes):
        pm = pd_map(tables, c, [0.0], override=override)
        summaries[c] = pm
        for i, row in enumerate(pm.rows):
            any_row = row == ANY_BAND
            line, = ax.plot(r_km, pm.pd[0, i], color="k" if any_row else colors(i), lw=2.4 if any_row else 1.2,
                            alpha=0.6 if any_row else 1.0, label=row_label(tables, row))
            line.set_gid(f"pd:{c}:{row}")
            if pm.beyond[0.1][i, 0]:
                ax.plot([r_km[-1]], [pm.pd[0, i, -1]], marker=">", ms=9, color=BEYOND_COLOR, ls="none", zorder=5)
        for level in PD_LEVELS:
            ax.axhline(level, color="0.5", lw=0.7, ls=LEVEL_STYLE[level]["ls"])
        past = [row for i, row in enumerate(pm.rows) if pm.beyond[0.1][i, 0]]
        ax.set_title(f"class {class_label(tables, c)}, {pm.terms.level_label}, {sigma_text(pm)}"
                     + (f"\nbeyond the table (P_D \u2265 0.1 at {r_km[-1]:g} km): {', '.join(past)}" if past else ""),
                     fontsize=9, color=BEYOND_COLOR if past else "k")
        ax.set_xlim(0.0, r_km[-1])
        ax.set_ylim(-0.02, 1.02)
        ax.set_xlabel("range, km")
        ax.set_ylabel("P_D, one look")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7.5, loc="lower left")
    fig.suptitle(f"Probability of detection P_D = \u03a6(SE / \u03c3) against range, area "
                 f"{tables.dataset.attrs['area']} (the same on every bearing)\n\u03c3: {pm.sigma.source}; "
                 f"dotted lines: P_D 0.9, 0.5, 0.1; \u25b6: P_D still \u2265 0.1 at the table's last range\n"
                 f"{tables.sonar_label()}",
                 fontsize=9)
    return fig, summaries


__all__ = ["BEYOND_COLOR", "pd_curves_figure", "pd_map_figure", "row_label", "sigma_text"]
