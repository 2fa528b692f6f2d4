"""Plots of a grid: TL fields (depth x range) per band and K(r) curves, BELLHOP beside Urick."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from acoustics.grid.flattables import FlatTables
from acoustics.plots.figures import new_figure, save_figure


def plot_flat_grid(tables: FlatTables, out: str | Path, *, cls_name: str | None = None) -> Path:
    """Write a PNG: one row per band, TL field of ``cls_name`` on the left, K(r) per class on the right.

    The analogues of Grinenkov & Mashoshin Fig. 3 (K(r) per band and class) and Iglesis &
    de Montella Fig. 1 (TL field over depth and range).
    """
    import matplotlib

    ds = tables.dataset
    cls_name = tables.class_names[0] if cls_name is None else cls_name
    bands = [str(b) for b in ds["band"].values]
    range_km = ds["range"].values / 1000.0
    depth = ds["depth"].values
    fig = new_figure(figsize=(13, 3.6 * len(bands)))
    axes = fig.subplots(len(bands), 2, squeeze=False, gridspec_kw={"width_ratios": [1.25, 1]})
    tl_all = ds["tl_db"].sel({"class": cls_name}).values
    finite = tl_all[np.isfinite(tl_all)]
    vmin, vmax = np.percentile(finite, [2, 98]) if finite.size else (40, 120)
    colors = matplotlib.colormaps["tab10"]
    for i, band in enumerate(bands):
        lo, hi = float(ds["band_low_hz"][i]), float(ds["band_high_hz"][i])
        label = f"{band} ({lo:g} Hz)" if lo == hi else f"{band} ({lo:g}-{hi:g} Hz)"
        ax = axes[i, 0]
        tl = ds["tl_db"].sel({"class": cls_name, "band": band}).values
        mesh = ax.pcolormesh(range_km, depth, tl, shading="auto", cmap="jet_r", vmin=vmin, vmax=vmax,
                             rasterized=True)
        ax.invert_yaxis()
        ax.set_ylabel("depth, m")
        ax.set_title(f"TL, class {cls_name} (source {float(ds['source_depth_m'].sel({'class': cls_name})):g} m), "
                     f"{label}", fontsize=9)
        ax.axhline(float(ds.attrs["observer_depth_m"]), color="w", lw=0.8, ls="--")
        fig.colorbar(mesh, ax=ax, label="TL, dB")
        ax = axes[i, 1]
        for j, c in enumerate(ds["class"].values):
            sel = {"class": c, "band": band}
            ax.plot(range_km, ds["k_db"].sel(sel), color=colors(j), lw=1.0, label=f"{c} {ds.attrs['model']}")
            ax.plot(range_km, ds["k_urick_db"].sel(sel), color=colors(j), lw=1.0, ls="--", label=f"{c} Urick")
        ax.set_ylabel("K(r), dB")
        ax.set_title(f"transfer characteristic at observer depth {ds.attrs['observer_depth_m']:g} m, {label}",
                     fontsize=9)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
    for ax in axes[-1]:
        ax.set_xlabel("range, km")
    fig.suptitle(f"area {ds.attrs['area']}", fontsize=11)
    fig.tight_layout()
    return save_figure(fig, out, dpi=110)
