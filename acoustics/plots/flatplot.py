"""Plots of a grid: TL fields (depth x range) per band and K(r) curves, BELLHOP beside Urick."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from acoustics.grid.flattables import FlatTables
from acoustics.plots.figures import new_figure, save_figure
from acoustics.plots.style import band_label


def plot_flat_grid(tables: FlatTables, out: str | Path, *, cls_name: str | None = None) -> Path:
    """Write a PNG: one row per band, TL field of ``cls_name`` on the left, K(r) per class on the right.

    The analogues of Grinenkov & Mashoshin Fig. 3 (K(r) per band and class) and Iglesis &
    de Montella Fig. 1 (TL field over depth and range).
    """
    import matplotlib

    cls_name = tables.class_names[0] if cls_name is None else cls_name
    ic = tables.class_index(cls_name)
    range_km = tables.range_m / 1000.0
    depth = tables.depth_m
    fig = new_figure(figsize=(13, 3.6 * len(tables.bands)))
    axes = fig.subplots(len(tables.bands), 2, squeeze=False, gridspec_kw={"width_ratios": [1.25, 1]})
    tl_all = tables.tl_db[ic]                                                    # (M, D, R)
    finite = tl_all[np.isfinite(tl_all)]
    vmin, vmax = np.percentile(finite, [2, 98]) if finite.size else (40, 120)
    colors = matplotlib.colormaps["tab10"]
    k_urick = tables.k_urick_grid_db
    for i, band in enumerate(tables.band_names):
        label = band_label(tables, band)
        ax = axes[i, 0]
        mesh = ax.pcolormesh(range_km, depth, tl_all[i], shading="auto", cmap="jet_r", vmin=vmin, vmax=vmax,
                             rasterized=True)
        ax.invert_yaxis()
        ax.set_ylabel("depth, m")
        ax.set_title(f"TL, class {cls_name} (source {tables.classes[ic].depth_m:g} m), {label}", fontsize=9)
        ax.axhline(tables.observer_depth_m, color="w", lw=0.8, ls="--")
        fig.colorbar(mesh, ax=ax, label="TL, dB")
        ax = axes[i, 1]
        for j, c in enumerate(tables.class_names):
            ax.plot(range_km, tables.k_grid_db[j, i], color=colors(j), lw=1.0, label=f"{c} {tables.model}")
            if k_urick is not None:
                ax.plot(range_km, k_urick[j, i], color=colors(j), lw=1.0, ls="--", label=f"{c} Urick")
        ax.set_ylabel("K(r), dB")
        ax.set_title(f"transfer characteristic at observer depth {tables.observer_depth_m:g} m, {label}",
                     fontsize=9)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
    for ax in axes[-1]:
        ax.set_xlabel("range, km")
    fig.suptitle(f"area {tables.area_name}", fontsize=11)
    fig.tight_layout()
    return save_figure(fig, out, dpi=110)
