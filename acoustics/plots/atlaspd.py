"""An atlas's probability of detection drawn: one month's map over the positions, and the months
side by side.

``tmakit atlas plot STORE --what pd``: a latitude-longitude panel over the water depth the
atlas's radials sampled, each position coloured by its median range where P_D = 0.5
(``acoustics.grid.atlas.seasons``; beyond the table its own colour, never a range) with its 0.5
outline around it, and a polar P_D panel for each of the first `MAX_POSITION_PANELS` positions
(``acoustics.plots.pdplot.pd_panel``).

``tmakit plan months STORE --plot PNG``: a panel per month with the same colours on one scale, and
a last panel naming at each position the month of the shortest median 0.5 range (the worst season
there). Artists carry ``gid``s: ``positions:MONTH`` (the scatter of the positions with a range:
its offsets are (lon, lat), its array the range in km), ``beyond:MONTH`` (the positions whose
median is beyond the table), ``outline:ORIGIN`` (a position's 0.5 outline, lon and lat).
"""

from __future__ import annotations

import math

import numpy as np

from acoustics.grid.atlas.seasons import PositionRange
from acoustics.grid.atlas.store import AtlasStore
from acoustics.plots.atlasmap import draw_atlas_relief
from acoustics.plots.figures import new_figure
from acoustics.plots.pdplot import BEYOND_COLOR, pd_panel
from acoustics.plots.style import DEG
from envdata.radials import geodesic_points

#: Positions drawn as polar panels beside the map (all are on the map).
MAX_POSITION_PANELS = 6
#: The colours of a range.
RANGE_CMAP = "viridis"


def _label(row: str) -> str:
    return "any band" if row == "any" else f"band {row}"


def _positions(ax, store: AtlasStore, rows: list[PositionRange], month: int, vmax_km: float):
    """The positions of one month, coloured by their median 0.5 range; beyond the table apart."""
    at = [r for r in rows if r.level == 0.5 and r.month == month]
    ranged = [r for r in at if not r.median_beyond_table]
    past = [r for r in at if r.median_beyond_table]
    sc = ax.scatter([r.lon_deg for r in ranged], [r.lat_deg for r in ranged], c=[r.median_m / 1000 for r in ranged],
                    s=110, cmap=RANGE_CMAP, vmin=0.0, vmax=vmax_km, edgecolors="k", zorder=4)
    sc.set_gid(f"positions:{month}")
    beyond = ax.scatter([r.lon_deg for r in past], [r.lat_deg for r in past], s=150, marker="o",
                        facecolors=BEYOND_COLOR, edgecolors="k", zorder=4,
                        label="median beyond the table (no range)")
    beyond.set_gid(f"beyond:{month}")
    if store.left_out:
        ax.scatter([p["lon_deg"] for p in store.left_out], [p["lat_deg"] for p in store.left_out], marker="x",
                   c="0.3", zorder=3, label="left out (land, shallow)")
    ax.set_aspect(1.0 / math.cos(math.radians(float(np.mean(store.lat_deg)))))
    ax.set_xlabel(f"longitude, {DEG}E", fontsize=8)
    ax.set_ylabel(f"latitude, {DEG}N", fontsize=8)
    ax.tick_params(labelsize=7)
    return sc


def atlas_pd_figure(store: AtlasStore, *, month: int, cls_name: str, row: str, maps: dict,
                    rows: list[PositionRange], override=None):
    """One month's P_D map of the atlas (module docstring); ``maps`` and ``rows`` from
    ``acoustics.grid.atlas.seasons``."""
    panels = list(maps)[:MAX_POSITION_PANELS]
    ncols = 1 + min(len(panels), 3)
    nrows = 1 if len(panels) <= 3 else 2
    fig = new_figure(figsize=(6.4 + 3.6 * (ncols - 1), 4.6 * nrows + 1.2), layout="constrained")
    grid = fig.add_gridspec(nrows, ncols, width_ratios=[1.7] + [1.0] * (ncols - 1))
    ax = fig.add_subplot(grid[:, 0])
    draw_atlas_relief(ax, store, colorbar=False)
    vmax = float(store.range_m[-1]) / 1000.0
    sc = _positions(ax, store, rows, month, vmax)
    for o, pm in maps.items():
        r50 = pm.ranges_m[0.5][pm.row(row)]
        lat, lon = np.full(r50.size + 1, np.nan), np.full(r50.size + 1, np.nan)   # gaps: no range there
        for j, (b, r) in enumerate(zip(pm.bearing_deg, r50)):
            if np.isfinite(r):
                la, lo = geodesic_points(store.lat_deg[o], store.lon_deg[o], float(b), [float(r)])
                lat[j], lon[j] = la[0], lo[0]
        lat[-1], lon[-1] = lat[0], lon[0]
        line, = ax.plot(lon, lat, color="k", lw=0.8, alpha=0.7, marker=".", ms=3)
        line.set_gid(f"outline:{o}")
        ax.annotate(str(o), (store.lon_deg[o], store.lat_deg[o]), xytext=(6, 6), textcoords="offset points",
                    fontsize=7)
    fig.colorbar(sc, ax=ax, orientation="horizontal", shrink=0.9, pad=0.02,
                 label="median range where P_D = 0.5 over the radials, km")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.22), fontsize=7)
    ax.set_title(f"month {month}: median P_D = 0.5 range at each position\nand its outline", fontsize=9)
    mesh, polar = None, []
    for j, o in enumerate(panels):
        pax = fig.add_subplot(grid[j // 3, 1 + j % 3], projection="polar")
        polar.append(pax)
        _, mesh = pd_panel(pax, store.sel(month=month, origin=o), cls_name, row, override=override)
        pax.set_title(f"position {o}: {store.lat_deg[o]:.3f}{DEG}N {store.lon_deg[o]:.3f}{DEG}E", fontsize=8)
        pax.tick_params(labelsize=6)
    if mesh is not None:
        fig.colorbar(mesh, ax=polar, orientation="horizontal", shrink=0.6, pad=0.02,
                     label=f"P_D in {_label(row)}, one look; lines: P_D 0.9 (solid), 0.5 (dashed), 0.1 (dotted); "
                           "magenta: beyond the table")
    first = next(iter(maps.values()))
    fig.suptitle(f"atlas {store.area.name}, class {cls_name} ({first.terms.level_label}), {_label(row)}, "
                 f"month {month}: P_D = \u03a6(SE / \u03c3)\n\u03c3: {first.sigma.source}", fontsize=9)
    return fig


def seasons_figure(store: AtlasStore, rows: list[PositionRange], *, cls_name: str, row: str, months: list[int]):
    """The months side by side, and the worst month at each position (module docstring)."""
    n = len(months) + (len(months) > 1)
    ncols = min(n, 5)
    nrows = math.ceil(n / ncols)
    fig = new_figure(figsize=(4.2 * ncols + 0.6, 4.2 * nrows + 1.0), layout="constrained")
    vmax = float(store.range_m[-1]) / 1000.0
    sc = None
    axes = []
    for i, month in enumerate(months):
        ax = fig.add_subplot(nrows, ncols, i + 1)
        draw_atlas_relief(ax, store, colorbar=False)
        sc = _positions(ax, store, rows, month, vmax)
        ax.set_title(f"month {month}", fontsize=9)
        axes.append(ax)
    if len(months) > 1:
        ax = fig.add_subplot(nrows, ncols, len(months) + 1)
        draw_atlas_relief(ax, store, colorbar=False)
        for o in sorted({r.origin for r in rows}):
            at = {r.month: r for r in rows if r.origin == o and r.level == 0.5}
            worst = min(months, key=lambda m: np.inf if at[m].median_beyond_table else at[m].median_m)
            everywhere = all(at[m].median_beyond_table for m in months)
            ax.plot([at[worst].lon_deg], [at[worst].lat_deg], marker="o", ms=15, ls="none", mec="k",
                    color=BEYOND_COLOR if everywhere else "white")
            ax.annotate("-" if everywhere else str(worst), (at[worst].lon_deg, at[worst].lat_deg), ha="center",
                        va="center", fontsize=8, fontweight="bold")
        ax.set_aspect(1.0 / math.cos(math.radians(float(np.mean(store.lat_deg)))))
        ax.set_title("the month of the shortest median P_D = 0.5\nrange at each position (magenta: beyond the "
                     "table in every month)", fontsize=9)
        ax.tick_params(labelsize=7)
        axes.append(ax)
    fig.colorbar(sc, ax=axes, orientation="horizontal", shrink=0.6, pad=0.02,
                 label="median range where P_D = 0.5 over the radials, km (magenta: beyond the table)")
    fig.suptitle(f"atlas {store.area.name}, class {cls_name}, {_label(row)}: the detection range per month "
                 f"(tables to {vmax:g} km)", fontsize=9.5)
    return fig


__all__ = ["atlas_pd_figure", "seasons_figure"]
