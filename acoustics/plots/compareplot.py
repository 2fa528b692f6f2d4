"""The picture of a grid comparison: the difference field B - A per class and band."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from acoustics.grid.compare import GridComparison
from acoustics.plots.figures import new_figure, save_figure

#: The colour scale's half-width, dB (differences beyond it saturate).
SCALE_DB = 10.0


def plot_comparison(comparison: GridComparison, out: str | Path) -> Path:
    """Write a PNG: one panel per class (rows) and band (columns), B - A over range and depth (TL,
    a flat grid) or over range and bearing (K, a bearing-dependent grid), a diverging scale of
    +-`SCALE_DB` dB; grey where the two grids are not compared (empty or shadow cells)."""
    import matplotlib

    c = comparison
    n_c, n_b = len(c.class_names), len(c.band_names)
    fig = new_figure(figsize=(4.6 * n_b + 1.2, 3.2 * n_c + 0.8), layout="constrained")
    axes = fig.subplots(n_c, n_b, squeeze=False)
    cmap = matplotlib.colormaps["RdBu_r"].with_extremes(bad="0.85")
    range_km = c.range_m / 1000.0
    quantity = "TL" if c.axis_name == "depth" else "K"
    mesh = None
    for ic, cls_name in enumerate(c.class_names):
        for ib, band in enumerate(c.band_names):
            ax = axes[ic, ib]
            field = np.ma.masked_invalid(c.field_db[ic, ib])
            mesh = ax.pcolormesh(range_km, c.axis_values, field, shading="auto", cmap=cmap,
                                 vmin=-SCALE_DB, vmax=SCALE_DB, rasterized=True)
            if c.axis_name == "depth":
                ax.invert_yaxis()
            ax.set_title(f"{cls_name}, {band}", fontsize=9)
            if ib == 0:
                ax.set_ylabel("depth, m" if c.axis_name == "depth" else "bearing, deg")
            if ic == n_c - 1:
                ax.set_xlabel("range, km")
    if mesh is not None:
        fig.colorbar(mesh, ax=axes, label=f"{quantity} {c.model_b} - {c.model_a}, dB", shrink=0.8)
    fig.suptitle(f"area {c.area}: {quantity} of {Path(c.source_b).name} ({c.model_b}) minus "
                 f"{Path(c.source_a).name} ({c.model_a})", fontsize=10)
    return save_figure(fig, out, dpi=100)
