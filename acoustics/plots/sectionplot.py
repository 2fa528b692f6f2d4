"""A TL section along one bearing of a bearing-dependent grid: the radial nearest to it.

``tl_db`` of one class and band over depth and range on the radial nearest to the bearing asked
for (across 0/360; halfway, the one counter-clockwise), with that radial's bottom. Not values
mixed between the two radials around the bearing: TL is computed per radial over its own bottom,
and a mean of two fields over different bottoms is no field at all (it ends at the shallower
bottom, a strip of nothing above the mean bottom). The maps, which show K, do interpolate in
bearing, as the trackers do. The observer at the origin and the class's depth (where K is read)
are marked; below, K(r) per band along the same radial and the K each band needs to be detected
at the class's mean level.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from acoustics.grid.detectionmap import class_terms
from acoustics.grid.radialtables import RadialTables
from acoustics.plots.figures import new_figure
from acoustics.plots.style import (
    DEG,
    LAND_COLOR,
    ORIGIN_STYLE,
    band_label,
    check_plot_options,
    class_label,
    origin_label,
)


def section_figure(tables: RadialTables, *, bearing_deg: float, cls_name: str | None = None,
                   band: str | None = None) -> Figure:
    """TL over depth and range on the radial nearest to ``bearing_deg``, for a class (default:
    the first) and band (default: the first).

    Notes
    -----
    Artists carry ``gid``s: ``section:tl`` (the TL mesh, depth x range), ``section:bottom``
    (depth in m against range in km), ``section:k:BAND`` (K(r) in dB against range in km).
    """
    import matplotlib

    cls_name = tables.class_names[0] if cls_name is None else cls_name
    band = tables.band_names[0] if band is None else band
    check_plot_options(tables, cls_name=cls_name, band=band, bearing_deg=bearing_deg)
    j = tables.nearest_radial(bearing_deg)
    ic, ib = tables.class_index(cls_name), tables.band_index(band)
    on = float(tables.bearing_deg[j])
    r_km = tables.range_m / 1000.0
    depth = tables.depth_m
    tl = tables.observer_tl_db()[ic, ib, j]                                            # (D, R)
    bottom = tables.bottom_depth_m[j]
    k = tables.k_grid_db[ic, :, j]                                                     # (M, R)
    obs = tables.observer_depth_m
    src = tables.classes[ic].depth_m
    fig = new_figure(figsize=(12.0, 8.2), layout="constrained")
    ax, ax_k = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [2.2, 1]})
    finite = tl[np.isfinite(tl)]
    vmin, vmax = np.percentile(finite, [2, 98]) if finite.size else (40.0, 120.0)
    mesh = ax.pcolormesh(r_km, depth, tl, shading="nearest", cmap="jet_r", vmin=vmin, vmax=vmax,
                         rasterized=True)
    mesh.set_gid("section:tl")
    fig.colorbar(mesh, ax=ax, pad=0.01, label="TL, dB (re 1 m)")
    wet = np.isfinite(bottom)
    z_max = float(np.nanmax(bottom)) * 1.05 if wet.any() else float(depth[-1])
    ax.fill_between(r_km, bottom, z_max, where=wet, color="0.55", lw=0)
    line, = ax.plot(r_km, bottom, color="k", lw=1.4, label="bottom")
    line.set_gid("section:bottom")
    if wet.any() and not wet[-1]:
        coast = r_km[np.flatnonzero(wet)[-1]]
        ax.axvspan(coast, r_km[-1], color=LAND_COLOR, label="land (no TL beyond the coast)")
        ax_k.axvspan(coast, r_km[-1], color=LAND_COLOR)
    ax.axhline(src, color="magenta", lw=1.0, ls="--", label=f"class {cls_name} depth {src:g} m (K is read here)")
    ax.plot([0.0], [obs], ms=14, clip_on=False, zorder=6, label=f"observer at the origin, {obs:g} m",
            **ORIGIN_STYLE)
    ax.set_xlim(0.0, r_km[-1])
    ax.set_ylim(z_max, 0.0)
    ax.set_ylabel("depth, m")
    ax.legend(fontsize=8, loc="lower right", framealpha=0.9)
    asked = (f"the radial {on:g}{DEG}" if on == bearing_deg
             else f"the radial {on:g}{DEG}, the nearest to {bearing_deg:g}{DEG}")
    ax.set_title(f"TL between the observer and a point at depth on {asked}; class {class_label(tables, cls_name)}, "
                 f"{band_label(tables, band)}", fontsize=9.5)
    terms = class_terms(tables, cls_name)
    need = terms.k_needed_db()
    colors = matplotlib.colormaps["tab10"]
    for i, b in enumerate(tables.band_names):
        line, = ax_k.plot(r_km, k[i], color=colors(i), lw=1.2, label=f"K(r) {band_label(tables, b)}")
        line.set_gid(f"section:k:{b}")
        ax_k.axhline(need[i], color=colors(i), lw=0.9, ls="--")
    ax_k.plot([], [], color="0.3", ls="--", lw=0.9,
              label=f"K a band needs to be detected ({terms.level_label}, Q \u2265 {terms.threshold:g})")
    ax_k.set_ylabel("K(r), dB")
    ax_k.set_xlabel(f"range from the origin along the radial {on:g}{DEG}, km")
    ax_k.grid(alpha=0.3)
    ax_k.legend(fontsize=7.5, ncol=2, loc="upper right", framealpha=0.9)
    ax_k.set_title(f"transfer characteristic on the radial, class {cls_name} at {src:g} m "
                   f"(blank: no K, the class deeper than the water or beyond land)", fontsize=9)
    fig.suptitle(f"area {tables.area_name}: section along {on:g}{DEG} from {origin_label(tables)}, "
                 f"observer at {obs:g} m", fontsize=10.5)
    return fig
