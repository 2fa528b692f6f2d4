"""The plot of the depth study: median position error and the depth estimate against time."""

from __future__ import annotations

import pandas as pd
from matplotlib.figure import Figure

from acoustics.plots.figures import new_figure

_METHOD = {"rpf": ("particle filter", "tab:red"), "ml": ("ML analysis", "tab:blue")}
_VARIANT = {"class": ("class's depth", ":"), "true": ("true depth", "-"), "unknown": ("depth unknown", "--")}


def depth_figure(frame: pd.DataFrame, summary: dict) -> Figure:
    """Left: median position error, m (log), per tracker and depth; right: depth estimates, m."""
    fig = new_figure(figsize=(11.0, 4.6), layout="constrained")
    ax, az = fig.subplots(1, 2)
    for method, (label, colour) in _METHOD.items():
        for variant, (vlabel, style) in _VARIANT.items():
            col = f"{method}_{variant}_median_error_m"
            if col in frame:
                ax.plot(frame["t_min"], frame[col], color=colour, ls=style, lw=1.4,
                        label=f"{label}, {vlabel}")
        col = f"{method}_unknown_depth_median_m"
        if col in frame:
            az.plot(frame["t_min"], frame[col], color=colour, lw=1.4, label=f"{label}: median")
            az.fill_between(frame["t_min"], frame[f"{method}_unknown_depth_p10_m"],
                            frame[f"{method}_unknown_depth_p90_m"], color=colour, alpha=0.15,
                            label=f"{label}: 10-90 % of runs")
    ax.set_yscale("log")
    ax.set_xlabel("time since the first cycle, min")
    ax.set_ylabel("median position error over runs, m")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    az.axhline(summary["true_depth_m"], color="k", lw=1.0, label="true depth")
    az.axhline(summary["class_depth_m"], color="grey", lw=1.0, ls=":", label="class's table depth")
    az.set_ylim(summary["depth_span_m"][1], 0.0)
    az.set_xlabel("time since the first cycle, min")
    az.set_ylabel("depth estimate, m")
    az.grid(alpha=0.3)
    az.legend(fontsize=7)
    fig.suptitle(f"{summary['scenario']} in {summary['area']}: {summary['runs']} runs, class "
                 f"{summary['class']} (tables at {summary['class_depth_m']:g} m), target at "
                 f"{summary['true_depth_m']:g} m, SPL band {summary['band']}", fontsize=10)
    return fig
