"""The plot of the shelf study: position RMSE against time, bearing-dependent grid and shortcut."""

from __future__ import annotations

import pandas as pd
from matplotlib.figure import Figure

from acoustics.plots.figures import new_figure

_STYLE = {"ml": ("ML motion analysis (G&M)", "tab:blue"), "rpf": ("particle filter, bearings + SPL", "tab:red"),
          "bot": ("particle filter, bearings only", "tab:gray")}
_GRID = {"bearing": ("bearing-dependent grid", "-"), "isotropic": ("origin's column, flat bottom", "--")}


def rmse_figure(frame: pd.DataFrame, summary: dict) -> Figure:
    """Position RMSE, m (log scale), against minutes, one line per tracker and grid."""
    fig = new_figure(figsize=(8.0, 4.8), layout="constrained")
    ax = fig.add_subplot()
    for method, (label, colour) in _STYLE.items():
        for grid, (grid_label, style) in _GRID.items():
            column = f"{method}_{grid}_rmse_m"
            if column in frame:
                ax.plot(frame["t_min"], frame[column], color=colour, ls=style, lw=1.4,
                        label=f"{label}, {grid_label}")
    ax.set_yscale("log")
    ax.set_xlabel("time since the first cycle, min")
    ax.set_ylabel("position RMSE, m")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    ax.set_title(f"{summary['scenario']} in {summary['area']}: {summary['runs']} runs, class "
                 f"{summary['class']}, SPL band {summary['band']}", fontsize=10)
    return fig
