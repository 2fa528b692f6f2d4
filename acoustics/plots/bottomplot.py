"""The bottom along the radials of a bearing-dependent grid.

README "What it does" (``grids plot``): the bottom along the radials. Left, ``bottom_depth_m`` against range,
one line per radial (coloured by bearing on a cyclic scale), a marker where a radial meets land
and the observer at the origin; right, the radials side by side as a range-bearing image with
the depth contours and land shaded.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from acoustics.grid.radialtables import RadialTables
from acoustics.plots.figures import new_figure
from acoustics.plots.style import DEG, LAND_COLOR, ORIGIN_STYLE, contour_levels, label_depth, origin_label


def bottom_figure(tables: RadialTables) -> Figure:
    """Water depth along every radial of a bearing-dependent grid.

    Notes
    -----
    Artists carry ``gid``s: ``bottom:BEARING`` (lines, depth in m against range in km) and
    ``land:BEARING`` (a marker at the last wet range of a radial that meets land).
    """
    import matplotlib
    from matplotlib.colors import ListedColormap, Normalize

    bearings = tables.bearing_deg
    r_km = tables.range_m / 1000.0
    bottom = tables.bottom_depth_m
    obs = tables.observer_depth_m
    deepest = float(np.nanmax(bottom)) if np.isfinite(bottom).any() else obs
    fig = new_figure(figsize=(14.0, 5.4), layout="constrained")
    ax, ax2 = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1.2, 1]})
    # a cyclic scale dark enough everywhere for lines on white (twilight fades to white at north)
    cmap = ListedColormap(matplotlib.colormaps["hsv"](np.linspace(0.0, 1.0, 256))[:, :3] * 0.8)
    coasts = []
    for b, row in zip(bearings, bottom):
        line, = ax.plot(r_km, row, color=cmap(float(b) / 360.0), lw=1.3)
        line.set_gid(f"bottom:{b:g}")
        wet = np.isfinite(row)
        if wet.any() and not wet[-1]:
            last = np.flatnonzero(wet)[-1]
            mark, = ax.plot([r_km[last]], [row[last]], marker="^", color=LAND_COLOR, mec="saddlebrown",
                            ms=9, ls="none", zorder=5, label=None if coasts else "radial meets land")
            mark.set_gid(f"land:{b:g}")
            coasts.append(f"{b:g}{DEG} at {r_km[last]:g} km")
    if coasts:  # name them in the legend: several coasts share a range and would hide each other's labels
        lines = [", ".join(coasts[i:i + 4]) for i in range(0, len(coasts), 4)]
        ax.plot([], [], ls="none", label="last water: " + ",\n".join(lines))
    ax.axhline(obs, color="crimson", lw=0.8, ls="--", label=f"observer depth {obs:g} m")
    ax.plot([0.0], [obs], ms=12, clip_on=False, zorder=6, label="observer at the origin", **ORIGIN_STYLE)
    ax.set_xlim(0.0, r_km[-1])
    ax.set_ylim(deepest * 1.05, -0.03 * deepest)
    ax.set_xlabel("range from the origin along the radial, km")
    ax.set_ylabel("water depth, m")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower left")
    cb = fig.colorbar(matplotlib.cm.ScalarMappable(norm=Normalize(0.0, 360.0), cmap=cmap), ax=ax, pad=0.01,
                      label=f"radial bearing, {DEG} from true north")
    ticks = bearings if bearings.size <= 12 else np.arange(0, 360, 45)
    cb.set_ticks(ticks)
    ax.set_title("bottom along each radial, one line per bearing", fontsize=9.5)
    r_edges, b_edges = _edges(r_km, 0.1), _edges(bearings, 10.0)
    mesh = ax2.pcolormesh(r_edges, b_edges, bottom, cmap="viridis_r", rasterized=True)
    ax2.pcolormesh(r_edges, b_edges, np.where(np.isfinite(bottom), np.nan, 1.0),
                   cmap=ListedColormap([LAND_COLOR]), vmin=0, vmax=1, rasterized=True)
    levels = contour_levels(bottom)
    if levels and bearings.size > 1:
        cs = ax2.contour(r_km, bearings, bottom, levels=levels, colors="w", linewidths=0.7)
        ax2.clabel(cs, fmt=label_depth, fontsize=6)
    ax2.set_yticks(ticks)
    ax2.set_xlabel("range from the origin, km")
    ax2.set_ylabel(f"radial bearing, {DEG} from true north")
    ax2.set_title("water depth by radial, each row one radial (tan: land beyond the coast)", fontsize=9.5)
    fig.colorbar(mesh, ax=ax2, pad=0.01, label="water depth, m")
    radials = "radial" if bearings.size == 1 else "radials"
    fig.suptitle(f"area {tables.area_name}: the bottom (bottom_depth_m) along the {bearings.size} {radials} "
                 f"from {origin_label(tables)}", fontsize=10.5)
    return fig


def _edges(centres: np.ndarray, width_if_one: float) -> np.ndarray:
    """Cell edges halfway between centres (the outer cells as wide as their neighbours); one
    centre gets a cell ``width_if_one`` wide."""
    c = np.asarray(centres, dtype=float)
    if c.size == 1:
        return np.array([c[0] - width_if_one / 2, c[0] + width_if_one / 2])
    mid = 0.5 * (c[1:] + c[:-1])
    return np.concatenate([[c[0] - (mid[0] - c[0])], mid, [c[-1] + (c[-1] - mid[-1])]])
