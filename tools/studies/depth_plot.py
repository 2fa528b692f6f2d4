"""The plot of the depth study: each run's 90 % depth interval against the true depth, for each
way of estimating the depth (the depth-state filter, retired, has no panel: docs/depth.md)."""

from __future__ import annotations

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from acoustics.plots.figures import new_figure

_SOURCE = {("ml", "unknown", "posterior"): ("ml_posterior", "ML analysis: posterior over its hypotheses' tracks"),
           ("rpf", "bank", "posterior"): ("rpf_bank", "bank of particle filters at the hypotheses"),
           ("known_motion", "unknown", "true_track"): ("known_motion_true_track",
                                                       "the motion known:\nposterior along the true track")}
_COLOURS = ("tab:blue", "tab:red", "tab:green", "tab:purple")


def depth_figure(frame: pd.DataFrame, summary: dict) -> Figure:
    """One panel per depth estimate: runs' 90 % intervals (bars) and medians (dots) at each true
    depth (x, jittered by scenario and run), the truth as a line; coverage in the title."""
    fig = new_figure(figsize=(13.0, 4.8), layout="constrained")
    axes = fig.subplots(1, len(_SOURCE), sharey=True)
    truths = summary["true_depths_m"]
    for ax, ((method, variant, source), (key, label)) in zip(np.atleast_1d(axes), _SOURCE.items()):
        d = frame[(frame["method"] == method) & (frame["variant"] == variant) & (frame["depth_from"] == source)]
        for s_i, sc in enumerate(summary["scenarios"]):
            g = d[d["scenario"] == sc]
            if g.empty:
                continue
            slot = np.array([truths.index(z) for z in g["true_depth_m"]], dtype=float)
            x = slot + 0.1 + 0.4 * s_i + 0.3 * g["run"].to_numpy() / max(int(g["run"].max()), 1)
            c = _COLOURS[s_i % len(_COLOURS)]
            ax.vlines(x, g["lo_m"], g["hi_m"], color=c, lw=0.8, alpha=0.7, label=sc)
            ax.plot(x, g["depth_m"], ".", color=c, ms=3)
        for i, z in enumerate(truths):
            ax.hlines(z, i, i + 1, color="k", lw=1.2)
        est = summary["depth_estimates"].get(key, {}).get("all", {})
        cover = est.get("coverage_90")
        ax.set_title(label + (f"\ncoverage {100 * cover:.0f} %" if cover is not None else ""), fontsize=9)
        ax.set_xticks(np.arange(len(truths)) + 0.5, [f"{z:g}" for z in truths])
        ax.set_xlabel("true depth, m")
        ax.set_ylim(summary["depth_span_m"][1], 0.0)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="lower left")
    np.atleast_1d(axes)[0].set_ylabel("final depth: 90 % interval and median, m")
    fig.suptitle(f"Depth study in {summary['area']}: {summary['runs']} runs per scenario and depth, class "
                 f"{summary['class']} (tables at {summary['class_depth_m']:g} m), levels from {summary['truth']}",
                 fontsize=10)
    return fig
