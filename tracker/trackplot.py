"""The picture a tracker's user looks at first: where the observer went, what it heard, and where
each class hypothesis puts the target, over the area.

Upper panel: the observer's path, a fan of its measured bearings (every few cycles, out to the
tracks' ranges), each class hypothesis's estimated track with its uncertainty ellipses at
intervals, and the truth when given; on latitude and longitude over the area's relief for a
bearing-dependent grid, on the local plane otherwise (``acoustics.plots.setting``). Lower panel,
with a truth: each hypothesis's position error against time.

The ellipses are 2-sigma, from the track's ``range_sd_m`` along the bearing and, across it, the
range times the measurements' bearing sd: the track CSV carries no cross-range sd of its own, so
this is the bearing's share alone.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from acoustics.grid.face import Tables
from acoustics.plots.figures import new_figure
from acoustics.plots.setting import draw_setting
from envdata.geometry import local_plane_to_lat_lon
from tracker.measurements import Measurements
from tracker.truthfile import Truth

#: Ellipses drawn per track, and bearing lines in the fan.
ELLIPSES = 8
FAN_LINES = 24


def track_figure(track: pd.DataFrame, measurements: Measurements, tables: Tables, *,
                 truth: Truth | None = None, grid_path=None):
    """The figure (module docstring); artists carry gids ``observer``, ``track:CLASS``,
    ``truth``, ``error:CLASS`` (metres against minutes)."""
    import matplotlib

    m = measurements
    classes = list(dict.fromkeys(track["class"]))
    colors = matplotlib.colormaps["tab10"]
    fig = new_figure(figsize=(10.5, 11.5 if truth is not None else 8.5), layout="constrained")
    if truth is not None:
        ax, ax_err = fig.subplots(2, 1, gridspec_kw={"height_ratios": [2.6, 1]})
    else:
        ax, ax_err = fig.subplots(1, 1), None
    reach = float(np.nanmax(np.hypot(np.concatenate([track.x_m, m.obs_x_m]),
                                     np.concatenate([track.y_m, m.obs_y_m]))))
    setting = draw_setting(tables, ax, radius_m=reach * 1.1, grid_path=grid_path)
    origin = tables.area.origin  # the reference of the local plane

    def to_axes(x, y):
        if setting.geographic:
            lat, lon = local_plane_to_lat_lon(origin.lat_deg, origin.lon_deg, x, y)
            return lon, lat
        return np.asarray(x) / 1000.0, np.asarray(y) / 1000.0

    # the bearing fan: measured bearings out to the tracks' median range
    fan_r = float(np.nanmedian(track.range_m)) * 1.3 if np.isfinite(track.range_m).any() else 10_000.0
    rows = np.flatnonzero(np.isfinite(m.bearing_deg))
    for i in rows[:: max(1, rows.size // FAN_LINES)]:
        b = math.radians(m.bearing_deg[i])
        s = np.linspace(0.0, fan_r, 12)
        fx, fy = to_axes(m.obs_x_m[i] + s * math.sin(b), m.obs_y_m[i] + s * math.cos(b))
        ax.plot(fx, fy, color="0.55", lw=0.5, alpha=0.6, zorder=2)
    ox, oy = to_axes(m.obs_x_m, m.obs_y_m)
    line, = ax.plot(ox, oy, color="k", lw=2.0, zorder=5, label="observer")
    line.set_gid("observer")
    ax.plot(ox[:1], oy[:1], "o", color="k", ms=5, zorder=5)
    sd_b = np.nanmedian(m.bearing_sigma_deg) if np.isfinite(m.bearing_sigma_deg).any() else 1.0
    for k, cls in enumerate(classes):
        rows_c = track[track["class"] == cls]
        tx, ty = to_axes(rows_c.x_m.to_numpy(), rows_c.y_m.to_numpy())
        line, = ax.plot(tx, ty, color=colors(k), lw=1.6, zorder=6, label=f"{cls} ({rows_c.method.iloc[0]})")
        line.set_gid(f"track:{cls}")
        for j in np.linspace(0, len(rows_c) - 1, min(ELLIPSES, len(rows_c))).astype(int)[1:]:
            r = rows_c.iloc[j]
            ex, ey = _ellipse(r.x_m, r.y_m, r.bearing_deg, 2.0 * r.range_sd_m,
                              2.0 * r.range_m * math.radians(sd_b))
            ax.plot(*to_axes(ex, ey), color=colors(k), lw=0.8, alpha=0.8, zorder=6)
    if truth is not None:
        tx, ty = to_axes(truth.x_m, truth.y_m)
        line, = ax.plot(tx, ty, color="crimson", lw=1.6, ls="--", zorder=7, label="truth")
        line.set_gid("truth")
        for k, cls in enumerate(classes):
            rows_c = track[track["class"] == cls]
            x, y = truth.at(rows_c.t_s.to_numpy())
            err = np.hypot(rows_c.x_m.to_numpy() - x, rows_c.y_m.to_numpy() - y)
            line, = ax_err.plot(rows_c.t_s.to_numpy() / 60.0, err, color=colors(k), lw=1.3, label=cls)
            line.set_gid(f"error:{cls}")
        ax_err.set_xlabel("time, min")
        ax_err.set_ylabel("position error, m")
        ax_err.set_yscale("log")
        ax_err.grid(alpha=0.3, which="both")
        ax_err.legend(fontsize=8)
    # frame the positions (observer, tracks, truth) with a margin, not the whole relief
    xs = np.concatenate([m.obs_x_m, track.x_m.to_numpy()] + ([truth.x_m] if truth is not None else []))
    ys = np.concatenate([m.obs_y_m, track.y_m.to_numpy()] + ([truth.y_m] if truth is not None else []))
    ok = np.isfinite(xs) & np.isfinite(ys)
    pad = max(2000.0, 0.2 * float(max(np.ptp(xs[ok]), np.ptp(ys[ok]))))
    (x0, x1), (y0, y1) = (to_axes([xs[ok].min() - pad, xs[ok].max() + pad], [ys[ok].min() - pad] * 2)[0],
                          to_axes([xs[ok].min() - pad] * 2, [ys[ok].min() - pad, ys[ok].max() + pad])[1])
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    if setting.geographic:
        ax.set_xlabel("longitude, deg E")
        ax.set_ylabel("latitude, deg N")
    else:
        ax.set_xlabel("x (east), km")
        ax.set_ylabel("y (north), km")
        ax.set_aspect("equal")
    ax.legend(fontsize=8, loc="best")
    ax.grid(alpha=0.25)
    ax.set_title(f"{len(m)} cycles of {m.source}; ellipses 2 sd (range sd along the bearing, bearing "
                 f"sd {sd_b:.2g} deg across)\n{setting.note}", fontsize=9)
    return fig


def _ellipse(x_m: float, y_m: float, bearing_deg: float, along_m: float, across_m: float):
    """Points of an ellipse centred at (x, y) with semi-axes ``along_m`` on the bearing and
    ``across_m`` across it, m."""
    a = np.linspace(0.0, 2.0 * math.pi, 49)
    b = math.radians(bearing_deg)
    u, v = along_m * np.cos(a), across_m * np.sin(a)      # along, across
    return x_m + u * math.sin(b) + v * math.cos(b), y_m + u * math.cos(b) - v * math.sin(b)
