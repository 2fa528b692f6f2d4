"""Plots of a sensitivity study: spread bands around the nominal K(r), maps of the TL sd."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import xarray as xr

from acoustics.plots.figures import new_figure, save_figure
from acoustics.sensitivity.face import Study


def plot_spread(study: Study, out: str | Path, *, atomic: bool = True) -> Path:
    """One panel per (class, band): nominal K(r), the 5-95 % member band and +-1 sd of K(r).

    Parameters
    ----------
    study : Study
        A study without bearings (or one radial of one, ``Study.along``).
    out : path
        PNG to write (atomically).

    Returns
    -------
    Path
        ``out``.
    """
    classes, bands = study.class_names, study.band_names
    range_km = study.range_m / 1000.0
    fig = new_figure(figsize=(4.2 * len(bands), 2.9 * len(classes)))
    axes = fig.subplots(len(classes), len(bands), squeeze=False, sharex=True)
    for i, cls_name in enumerate(classes):
        for j, band in enumerate(bands):
            ax = axes[i, j]
            k = study.k_db[:, i, j]
            nominal = study.k_nominal_db[i, j]
            with np.errstate(invalid="ignore"), warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)  # ranges with no K (beyond land)
                lo, hi = np.nanpercentile(k, [5, 95], axis=0)
                sd = np.nanstd(k, axis=0, ddof=1) if k.shape[0] > 1 else np.zeros_like(nominal)
                mean = np.nanmean(k, axis=0)
            ax.fill_between(range_km, lo, hi, color="tab:blue", alpha=0.25, lw=0, label="members 5-95 %")
            ax.plot(range_km, mean + sd, color="tab:blue", lw=0.6, ls="--", label="member mean +- 1 sd")
            ax.plot(range_km, mean - sd, color="tab:blue", lw=0.6, ls="--")
            ax.plot(range_km, nominal, color="k", lw=0.9, label="nominal")
            ax.set_title(f"{cls_name} {band}", fontsize=9)
            ax.grid(alpha=0.3)
            if j == 0:
                ax.set_ylabel("K(r), dB")
            if i == len(classes) - 1:
                ax.set_xlabel("range, km")
    axes[0, 0].legend(fontsize=7, loc="upper right")
    fig.suptitle(f"K(r) spread over {study.members} members, area {study.name}", fontsize=10)
    fig.tight_layout()
    return save_figure(fig, out, dpi=110, atomic=atomic)


def plot_sd_map(study: Study, out: str | Path, *, band: str | None = None,
                atomic: bool = True) -> Path:
    """Maps of the sd over members of band TL over depth and range, one per class.

    Parameters
    ----------
    study : Study
        A study run with ``tl=True``, without bearings (or one radial of one, ``Study.along``).
    out : path
        PNG to write (atomically).
    band : str, optional
        Band to draw; default the first.

    Returns
    -------
    Path
        ``out``.
    """
    if study.tl_db is None:
        raise ValueError("the study has no tl_db (run it with --tl)")
    band = study.band_names[0] if band is None else band
    classes = study.class_names
    fig = new_figure(figsize=(5.2 * len(classes), 3.8))
    axes = fig.subplots(1, len(classes), squeeze=False)
    range_km = study.range_m / 1000.0
    depth = study.depth_m
    for ic, (ax, cls_name) in enumerate(zip(axes[0], classes)):
        tl = study.tl_db[:, ic, study.band_names.index(band)]
        sd = np.nanstd(tl, axis=0, ddof=1) if tl.shape[0] > 1 else np.zeros(tl.shape[1:])
        mesh = ax.pcolormesh(range_km, depth, sd, shading="auto", cmap="magma_r", vmin=0,
                             vmax=float(np.nanpercentile(sd, 99)) or 1.0)
        ax.invert_yaxis()
        ax.set_title(f"sd of TL, {cls_name} {band}", fontsize=9)
        ax.set_xlabel("range, km")
        ax.set_ylabel("depth, m")
        fig.colorbar(mesh, ax=ax, label="dB")
    fig.tight_layout()
    return save_figure(fig, out, dpi=110, atomic=atomic)


def plot_polar_sd(study: Study, summary: xr.Dataset, out: str | Path, *, atomic: bool = True) -> Path:
    """A polar map of the sd over members of K per class (rows) and band (columns), around the
    origin of a bearing-dependent study (north up, bearings clockwise, range in km).

    Parameters
    ----------
    study : Study
        A study with bearings.
    summary : Dataset
        Its summaries (``k_sd_db(class, band, bearing, range)``).
    out : path
        PNG to write.

    Returns
    -------
    Path
        ``out``.
    """
    classes, bands = study.class_names, study.band_names
    bearings = study.bearing_deg
    theta = np.radians(bearings)
    r_km = study.range_m / 1000.0
    sd = summary["k_sd_db"].transpose("class", "band", "bearing", "range").values
    # each radial drawn as the wedge of bearings nearest to it (every degree, so the wedges are round)
    fine_deg = np.arange(0.0, 360.5, 1.0)
    nearest = np.argmin(np.abs((fine_deg[:, None] - bearings[None, :] + 180.0) % 360.0 - 180.0), axis=1)
    vmax = float(np.nanpercentile(sd, 98)) if np.isfinite(sd).any() else 1.0
    fig = new_figure(figsize=(3.6 * len(bands) + 0.6, 3.7 * len(classes) + 1.0), layout="constrained")
    axes = []
    mesh = None
    for i, cls_name in enumerate(classes):
        for j, band in enumerate(bands):
            ax = fig.add_subplot(len(classes), len(bands), i * len(bands) + j + 1, projection="polar")
            mesh = ax.pcolormesh(np.radians(fine_deg), r_km, sd[i, j][nearest].T, shading="nearest",
                                 cmap="magma_r", vmin=0.0, vmax=vmax or 1.0, rasterized=True)
            for b in theta:
                ax.plot([b, b], [0.0, r_km[-1]], color="0.5", lw=0.4, ls=":")
            ax.set_theta_zero_location("N")
            ax.set_theta_direction(-1)
            ax.set_rlim(0.0, r_km[-1])
            ax.tick_params(labelsize=6)
            ax.set_title(f"{cls_name} {band}", fontsize=9)
            axes.append(ax)
    fig.colorbar(mesh, ax=axes, orientation="horizontal", shrink=0.6, aspect=40,
                 label="sd over members of K(r), dB (blank: no K, beyond land or the class below the bottom)")
    fig.suptitle(f"sd of K over {study.members} members, area {study.name}: each radial "
                 f"(dotted) drawn over the bearings nearest to it; north up, range in km", fontsize=10)
    return save_figure(fig, out, dpi=110, atomic=atomic)


def spread_bearing_deg(summary: xr.Dataset) -> float:
    """The bearing whose K moves most (the largest mean sd of K over classes, bands and ranges), deg."""
    sd = summary["k_sd_db"].transpose("bearing", ...).values.reshape(summary.sizes["bearing"], -1)
    with np.errstate(invalid="ignore"):
        mean = np.array([np.nanmean(row) if np.isfinite(row).any() else -np.inf for row in sd])
    return float(summary["bearing"].values[int(np.argmax(mean))])


def plot_spread_along(study: Study, bearing_deg: float, out: str | Path, *, atomic: bool = True) -> Path:
    """`plot_spread` along one radial of a bearing-dependent study (the nearest to ``bearing_deg``)."""
    return plot_spread(study.along(study.radial_index(bearing_deg)), out, atomic=atomic)
