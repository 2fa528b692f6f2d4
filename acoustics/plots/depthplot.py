"""K against the target's depth and range along one bearing: what the trackers read with the
target's depth unknown (``tmakit grids plot FILE --out PNG --what depth``).

K(z, r) = S - TL_obs(z, r) of one class and band (``Tables.target_depth_k``,
``acoustics.grid.targetdepth``): on a bearing-dependent grid along the radial nearest to the
bearing asked for (not mixed between two radials, for the reason ``acoustics.plots.sectionplot``
gives), on a flat grid built with ``tl_obs_db`` its one column (the same along every bearing).
Marked: the class's table depth (where its own K(r) is computed), the span a target of the class
may be at (its ``depth_range_m``, else the water the tables hold: the depth-state filter's
prior) and the observer. Cells without water are left blank on a grey ground.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from acoustics.grid.face import Tables
from acoustics.plots.figures import new_figure, save_figure
from acoustics.plots.style import DEG, DPI, ORIGIN_STYLE, band_label, check_plot_options, class_label

#: Colour limits: these percentiles of the finite K of the slab (a few cells near the source
#: or in a shadow would otherwise take the whole scale).
K_PERCENTILES = (2.0, 98.0)


def depth_k_figure(tables: Tables, *, cls_name: str | None = None, band: str | None = None,
                   bearing_deg: float | None = None) -> Figure:
    """K against target depth and range for a class (default: the first) and band (default: the
    first), on the radial nearest to ``bearing_deg`` (default: the first radial) or a flat
    grid's one column.

    Notes
    -----
    Artists carry ``gid``s: ``depth:k`` (the K mesh, dB, depth x range, the face's
    ``target_depth_k`` slab), ``depth:table`` (the class's table depth, m), ``depth:span:min``
    and ``depth:span:max`` (the span's ends, m), ``observer``.

    Raises
    ------
    InputError
        A class or band the grid does not have, a bearing outside [0, 360) deg.
    GridFileError
        A flat grid built without ``tl_obs_db`` (no K at other target depths).
    """
    cls_name = tables.class_names[0] if cls_name is None else cls_name
    band = tables.band_names[0] if band is None else band
    check_plot_options(tables, cls_name=cls_name, band=band, bearing_deg=bearing_deg)
    ic, ib = tables.class_index(cls_name), tables.band_index(band)
    target_k = tables.target_depth_k(ic, ib)
    j, on = target_k.nearest_slab(bearing_deg)
    k = target_k.k_db[j]                                                     # (Z, R)
    cls = tables.classes[ic]
    lo, hi = tables.target_depth_span_m(ic)
    r_km = target_k.range_m / 1000.0
    depth = target_k.depth_m
    wet_rows = np.isfinite(k).any(axis=1)
    z_max = float(depth[wet_rows][-1]) if wet_rows.any() else float(depth[-1])
    z_max = max(z_max, hi, cls.depth_m, tables.observer_depth_m) * 1.03

    fig = new_figure(figsize=(11.0, 6.4), layout="constrained")
    ax = fig.subplots()
    ax.set_facecolor("0.55")  # no water: the bottom, or land beyond a coast
    finite = k[np.isfinite(k)]
    vmin, vmax = np.percentile(finite, K_PERCENTILES) if finite.size else (-100.0, 0.0)
    mesh = ax.pcolormesh(r_km, depth, k, shading="nearest", cmap="jet", vmin=vmin, vmax=vmax,
                         rasterized=True)
    mesh.set_gid("depth:k")
    fig.colorbar(mesh, ax=ax, pad=0.01, label=f"K, dB ({band_label(tables, band)})")
    line = ax.axhline(cls.depth_m, color="magenta", lw=1.4, ls="--",
                      label=f"class {cls_name}'s table depth {cls.depth_m:g} m (its own K(r))")
    line.set_gid("depth:table")
    said = ("depth_range_m" if cls.depth_range_m is not None
            else "no depth_range_m: the water the tables hold")
    for end, z in (("min", lo), ("max", hi)):
        line = ax.axhline(z, color="k", lw=1.3, ls=(0, (4, 2)),
                          label=f"where the target may be, {lo:.0f}-{hi:.0f} m ({said})" if end == "min" else None)
        line.set_gid(f"depth:span:{end}")
    obs, = ax.plot([0.0], [tables.observer_depth_m], ms=14, clip_on=False, zorder=6,
                   label=f"observer, {tables.observer_depth_m:g} m", **ORIGIN_STYLE)
    obs.set_gid("observer")
    ax.set_xlim(0.0, r_km[-1])
    ax.set_ylim(z_max, 0.0)
    ax.set_ylabel("target depth, m")
    where = ("a flat grid: the same along every bearing" if on is None
             else f"the radial {on:g}{DEG}" + ("" if bearing_deg is None or on == bearing_deg
                                              else f", the nearest to {bearing_deg:g}{DEG}"))
    ax.set_xlabel("range from the observer, km" + ("" if on is None else f" along {on:g}{DEG}"))
    ax.legend(fontsize=8, loc="lower right", framealpha=0.9)
    ax.set_title(f"K with the target at any depth (S - TL from the observer), class "
                 f"{class_label(tables, cls_name)}, {band_label(tables, band)}; {where}", fontsize=9.5)
    fig.suptitle(f"area {tables.area_name}: K against target depth and range", fontsize=10.5)
    return fig


def plot_target_depth(tables: Tables, out: str | Path, *, cls_name: str | None = None,
                      band: str | None = None, bearing_deg: float | None = None,
                      dpi: int = DPI) -> Path:
    """Write `depth_k_figure` as PNG to ``out`` (through a temporary file); returns the path."""
    fig = depth_k_figure(tables, cls_name=cls_name, band=band, bearing_deg=bearing_deg)
    return save_figure(fig, out, dpi=dpi)
