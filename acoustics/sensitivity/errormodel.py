"""K's error model measured by a study's members (`acoustics.grid.kerror`): dK(r) = K_member(r) -
K_nominal(r) split into the offset each member keeps along range and the residual that changes
along it.

Per class and band (and bearing), over the study's range window:

- ``k_offset_sd_db``: the rms over members of each member's range-mean dK (its bias included:
  the trackers do not correct the tables by it, so it is part of what they must allow for);
- ``k_residual_sd_db``: the rms of what that offset leaves, dK - offset;
- per class, ``k_residual_length_m``: the range over which the residual decorrelates, the lag
  (interpolated, over every member, band and bearing pooled) at which its correlation along
  range falls to 1/e;
- per class, ``k_offset_band_correlation``: the correlation between bands of the members'
  offsets (every pair of bands, every bearing pooled; clipped to [0, 1]).

The residual's length is measured along the radials (the study computes K per radial); a track
that crosses bearings meets the residual at the same scale by assumption.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import xarray as xr

from acoustics.grid.kerror import MODEL_VARS
from acoustics.sensitivity.face import Study

#: The residual's correlation is read out to this many range steps (lags beyond are not used).
MAX_LAG_STEPS = 60


def k_error_model(study: Study, range_min_m: float | None = None, range_max_m: float | None = None) -> xr.Dataset:
    """The model's variables measured by ``study`` (module docstring), on its class, band [and
    bearing] coordinates; NaN where no member has K."""
    ds = study.dataset
    rng = study.range_m
    lo = rng[0] if range_min_m is None else range_min_m
    hi = rng[-1] if range_max_m is None else range_max_m
    inside = (rng >= lo) & (rng <= hi)
    nominal = np.asarray(study.k_nominal_db, dtype=float)[None, ..., inside]
    dk = np.asarray(study.k_db, dtype=float)[..., inside] - nominal
    offset_sd, residual_sd, lengths, corrs = measure(dk, rng[inside])
    radial = study.bearing_deg is not None
    dims = ("class", "band", "bearing") if radial else ("class", "band")
    names = list(MODEL_VARS)
    attrs = {"k_offset_sd_db": {"units": "dB", "long_name": "sd of K's error that persists along a track (rms over "
                                                            "members of each member's range-mean K - K_nominal)"},
             "k_residual_sd_db": {"units": "dB", "long_name": "sd of K's error that changes along a track (rms of "
                                                              "K - K_nominal less each member's offset)"},
             "k_residual_length_m": {"units": "m", "long_name": "correlation length of the residual along range "
                                                                "(1/e)"},
             "k_offset_band_correlation": {"units": "1", "long_name": "correlation of the offset between bands"}}
    data = {names[0]: (dims, offset_sd, attrs[names[0]]), names[1]: (dims, residual_sd, attrs[names[1]]),
            names[2]: (("class",), lengths, attrs[names[2]]), names[3]: (("class",), corrs, attrs[names[3]])}
    coords = {"class": ds["class"].values, "band": ds["band"].values,
              **({"bearing": study.bearing_deg} if radial else {})}
    return xr.Dataset(data, coords=coords, attrs={"summary_range_min_m": float(lo), "summary_range_max_m": float(hi),
                                                  "members": study.members})


def measure(dk_db, range_m) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The model's numbers from K's error of every member (module docstring).

    Parameters
    ----------
    dk_db : array_like, shape (E, C, M, [N,] R)
        K_member - K_nominal, dB; NaN where a cell has no K.
    range_m : array_like, shape (R,)
        Its range axis, m (evenly spaced: the correlation length is read in its steps).

    Returns
    -------
    offset_sd_db, residual_sd_db : ndarray, shape (C, M, [N])
    residual_length_m, band_correlation : ndarray, shape (C,)
    """
    dk = np.asarray(dk_db, dtype=float)
    r = np.asarray(range_m, dtype=float)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)   # cells without K: NaN, left out
        offset = np.nanmean(dk, axis=-1)                                         # (E, C, M, [N])
        offset_sd = np.sqrt(np.nanmean(offset ** 2, axis=0))
        residual = dk - offset[..., None]
        residual_sd = np.sqrt(np.nanmean(residual ** 2, axis=(0, -1)))
    step = float(np.median(np.diff(r))) if r.size > 1 else math.nan
    lengths, corrs = [], []
    for ic in range(dk.shape[1]):
        lengths.append(_e_folding_m(residual[:, ic].reshape(-1, r.size), step))
        corrs.append(_band_correlation(offset[:, ic]))
    return offset_sd, residual_sd, np.asarray(lengths, dtype=float), np.asarray(corrs, dtype=float)


def _e_folding_m(rows: np.ndarray, step_m: float) -> float:
    """The lag at which the pooled autocorrelation of the rows (series along range, NaN where
    no K) falls to 1/e, m (interpolated between lags; NaN where it cannot be read)."""
    if not math.isfinite(step_m):
        return math.nan
    x = np.asarray(rows, dtype=float)
    x = x - np.nanmean(x, axis=1, keepdims=True)
    var = np.nanmean(x * x)
    if not (np.isfinite(var) and var > 0):
        return math.nan
    target = math.exp(-1.0)
    prev = 1.0
    for lag in range(1, min(MAX_LAG_STEPS, x.shape[1] - 1) + 1):
        c = float(np.nanmean(x[:, :-lag] * x[:, lag:]) / var)
        if not math.isfinite(c):
            return math.nan
        if c <= target:  # between lag - 1 (prev) and lag (c)
            return step_m * (lag - 1 + (prev - target) / max(prev - c, 1e-12))
        prev = c
    return step_m * MAX_LAG_STEPS


def _band_correlation(offsets: np.ndarray) -> float:
    """Correlation of the members' offsets between bands, every pair of bands (and bearings)
    pooled, in [0, 1]; 1 with a single band."""
    off = np.asarray(offsets, dtype=float)              # (member, band[, bearing])
    n_bands = off.shape[1]
    if n_bands < 2:
        return 1.0
    a, b = [], []
    for i in range(n_bands):
        for j in range(i + 1, n_bands):
            a.append(off[:, i].ravel())
            b.append(off[:, j].ravel())
    a, b = np.concatenate(a), np.concatenate(b)
    ok = np.isfinite(a) & np.isfinite(b)
    if ok.sum() < 3:
        return 1.0
    # about zero, not the mean: the bias is part of the offset the trackers allow for
    c = float(np.sum(a[ok] * b[ok]) / math.sqrt(np.sum(a[ok] ** 2) * np.sum(b[ok] ** 2)))
    return min(max(c, 0.0), 1.0)
