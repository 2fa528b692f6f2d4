"""Plots of the Iglesis & de Montella study: position RMSE vs time (analogues of Figs. 3, 5, 7).

Figures come from `acoustics.plots.figures.new_figure` (the Agg canvas, no pyplot state); the study
writes them with `acoustics.plots.figures.save_figure` at `DPI`.
"""

from __future__ import annotations

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from acoustics.plots.figures import new_figure
from tools.studies.idm_columns import COLUMN

#: Resolution of the PNG files, dots per inch.
DPI = 110

_STYLE = {"rpf-bot": ("BOT (RPF)", "tab:red", "-"),
          "rpf": ("BOT + SPL (RPF)", "tab:blue", "-"),
          "rpf-vp": ("BOT + SPL, variance-preserving kernel", "tab:purple", "-"),
          "rpf-sl": ("BOT + SPL, VP kernel, joint SL offset", "tab:green", "-")}


def rmse_figure(frame: pd.DataFrame, scenario, methods, *, runs: int) -> Figure:
    """Position RMSE of each filter and the BOT CRLB against time, log scale, with the paper's
    reported points as markers."""
    fig = new_figure(figsize=(7.5, 4.6))
    ax = fig.add_subplot(1, 1, 1)
    t = frame["t_min"].to_numpy()
    for m in methods:
        label, color, ls = _STYLE[m]
        ax.plot(t, frame[f"rmse_{COLUMN[m]}_m"], color=color, ls=ls, lw=1.6, label=label)
    ax.plot(t, frame["crlb_bot_m"], color="k", ls="--", lw=1.2, label="BOT CRLB (no process noise)")
    if "crlb_spl_m" in frame:
        ax.plot(t, frame["crlb_spl_m"], color="0.45", ls=":", lw=1.4,
                label="BOT+SPL CRLB (no process noise)")
    paper = scenario.paper or {}
    for key, value in paper.items():
        parts = key.split("_")
        if len(parts) == 3 and parts[1].endswith("min") and parts[0] in ("bot", "spl"):
            tm = float(parts[1][:-3])
            color = _STYLE["rpf-bot" if parts[0] == "bot" else "rpf"][1]
            ax.plot([tm], [value], marker="o", mfc="none", color=color, ls="none", ms=8)
        if key.startswith("bot_over_spl_") and key.endswith("min"):
            # the paper gives only the ratio BOT / BOT+SPL here: place it under our BOT RMSE
            tm = float(key[len("bot_over_spl_"):-3])
            i = int(np.argmin(np.abs(t - tm)))
            ax.plot([tm], [frame["rmse_bot_m"].iloc[i] / value], marker="s", mfc="none",
                    color=_STYLE["rpf"][1], ls="none", ms=8,
                    label=f"our BOT / the paper's ratio {value:g}")
    if any(k.endswith("min_m") for k in paper):
        ax.plot([], [], marker="o", mfc="none", color="gray", ls="none", label="paper's values")
    if scenario.turn is not None:
        ax.axvspan(scenario.turn[0] / 60.0, scenario.turn[1] / 60.0, color="0.9", zorder=0,
                   label="observer turn")
    ax.set_yscale("log")
    ax.set_xlim(0, t[-1])
    ax.set_xlabel("time, min")
    ax.set_ylabel("position RMSE, m")
    ax.set_title(f"{scenario.name}: {runs} runs", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    return fig
