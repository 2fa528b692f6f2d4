"""Error models and level-based ML ranging (Grinenkov & Mashoshin eqs. 2, 11, 20, 21).

Everything here is vectorised over a leading batch axis (class hypotheses, Monte Carlo runs),
so that one code path serves the one-cycle tracker API and the 1331-run experiment.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from tracker.errors import MeasurementFileError


@dataclass(frozen=True, slots=True, kw_only=True)
class ClassInfo:
    """A class hypothesis as the tracker needs it (Table 1 statistics)."""

    name: str
    speed_mean_mps: float
    speed_sd_mps: float
    noise_mean_db: float   # P0, dB re 1 uPa (1 Hz, 1 kHz, 1 m)
    noise_sd_db: float
    k_error_sd_db: float


@dataclass(frozen=True, slots=True, kw_only=True)
class SonarInfo:
    """Receiver and environment figures from the grid's area (eqs. 2, 11, 12)."""

    beamwidth_deg: float
    directivity_index_db: float
    integration_time_s: float
    detection_threshold: float
    receiver_gain_db: float
    noise_band_db: tuple[float, ...]   # sea-noise band level per band, dB re 1 uPa
    bandwidth_hz: tuple[float, ...]    # per band, Hz (1 Hz for a single frequency)


def grid_area(grid: xr.Dataset) -> dict:
    """The area description stored in a grid (attribute ``area_json``)."""
    text = grid.attrs.get("area_json")
    if not text:
        raise MeasurementFileError("grid: no area_json attribute; rebuild the grid with "
                                   "tmakit grids build")
    return json.loads(text)


def class_infos(grid: xr.Dataset) -> tuple[ClassInfo, ...]:
    """Class hypotheses of the grid, in grid order."""
    area = grid_area(grid)
    by_name = {c["name"]: c for c in area["classes"]}
    out = []
    for name in grid["class"].values:
        c = by_name[str(name)]
        if c.get("noise_mean_db") is None:
            raise MeasurementFileError(f"grid: class {name!r} has no noise_mean_db; the ML "
                                       f"tracker needs P0 (source_level_model = 'p0')")
        out.append(ClassInfo(name=str(name), speed_mean_mps=float(c["speed_mean_mps"]),
                             speed_sd_mps=float(c["speed_sd_mps"]),
                             noise_mean_db=float(c["noise_mean_db"]),
                             noise_sd_db=float(c["noise_sd_db"]),
                             k_error_sd_db=float(c["k_error_sd_db"])))
    return tuple(out)


def sonar_info(grid: xr.Dataset) -> SonarInfo:
    """Sonar and sea-noise figures of the grid's area."""
    from envdata.bands import Band
    from envdata.noise import Noise

    area = grid_area(grid)
    s = area["sonar"]
    noise = Noise(**area["noise"])
    bands = {b["name"]: Band(**b) for b in area["bands"]}
    names = [str(b) for b in grid["band"].values]
    return SonarInfo(beamwidth_deg=float(s["beamwidth_deg"]),
                     directivity_index_db=float(s["directivity_index_db"]),
                     integration_time_s=float(s["integration_time_s"]),
                     detection_threshold=float(s["detection_threshold"]),
                     receiver_gain_db=float(s.get("receiver_gain_db", 0.0)),
                     noise_band_db=tuple(noise.band_level_db(bands[n]) for n in names),
                     bandwidth_hz=tuple(1.0 if bands[n].is_single_frequency
                                        else bands[n].width_hz for n in names))


def bearing_sd_deg(beamwidth_deg, q_ind):
    """RMS bearing error, deg (eq. 2): sigma_P = 0.2 * beamwidth / Q_ind.

    Parameters
    ----------
    beamwidth_deg : float
        Width of the array's beam, deg.
    q_ind : array_like
        Indicator (output) SNR Q = q sqrt(df T), linear.
    """
    return 0.2 * np.asarray(beamwidth_deg, dtype=float) / np.asarray(q_ind, dtype=float)


def level_sd_db(q, bandwidth_hz, integration_time_s):
    """RMS error of a band level estimate, dB (eq. 11 = A2.6).

    sigma = 10 lg(1 + sqrt((q + 1)^2 + 1) / (q sqrt(df T))), q the linear power SNR at the
    output of the linear part of the receiver. At the indicator SNR q sqrt(df T) = 5 and small q
    this is 10 lg(1 + sqrt(2)/5) = 1.08 dB, the paper's "does not exceed 1.1 dB".
    """
    q = np.asarray(q, dtype=float)
    return 10.0 * np.log10(1.0 + np.sqrt((q + 1.0) ** 2 + 1.0)
                           / (q * np.sqrt(np.asarray(bandwidth_hz) * integration_time_s)))


def indicator_snr(snr_db, bandwidth_hz, integration_time_s):
    """Indicator SNR Q = q sqrt(df T) from the power SNR 10 lg q, dB (DESIGN.md)."""
    return 10.0 ** (np.asarray(snr_db, dtype=float) / 10.0) * np.sqrt(
        np.asarray(bandwidth_hz) * integration_time_s)


def offset_nodes(noise_sd_db: float, k_error_sd_db: float, n: int = 5):
    """Quadrature nodes of eq. 21 over p in mP0 +- 2 sP0 and dK in +- 2 sigma_dK.

    Only the sum c = (p - mP0) + dK enters eq. 20, so the n x n product rule is returned as
    offsets c, dB, and normalised normal-density weights.
    """
    u = np.linspace(-2.0, 2.0, n)
    w = np.exp(-0.5 * u ** 2)
    c = (u[:, None] * noise_sd_db + u[None, :] * k_error_sd_db).ravel()
    ww = (w[:, None] * w[None, :]).ravel()
    return c, ww / ww.sum()


def level_range(level_db, detected, sd_db, p0_db, k_db, range_m, *, offsets_db=(0.0,),
                weights=None, gain_db: float = 0.0):
    """Level-based ML range (eq. 20) and its a-posteriori RMS error (eq. 21), batched.

    Parameters
    ----------
    level_db : ndarray, shape (B, M)
        Measured band levels W_k, dB re 1 uPa (any value where not detected).
    detected : ndarray of bool, shape (B, M)
        Detection indicators I_k.
    sd_db : ndarray, shape (B, M)
        Level error sd sigma_dW_k (eq. 11), dB.
    p0_db : ndarray, shape (B,)
        Expected noise level P0 of the class hypothesis, dB re 1 uPa.
    k_db : ndarray, shape (M, R)
        Transfer characteristic K_k(r) of the class, dB (eq. 12).
    range_m : ndarray, shape (R,)
        Range axis of ``k_db``, m.
    offsets_db, weights : sequence
        Offsets c = (p - mP0) + dK of eq. 21 and their weights (``offset_nodes``).
    gain_db : float
        Receiver gain H_k, dB.

    Returns
    -------
    r_opt_m : ndarray, shape (B,)
        argmin_r sum_k I_k (W_k - P0 - K_k(r) - H)^2 / sigma_k^2 (eq. 20); NaN where no band
        is detected.
    r_sd_m : ndarray, shape (B,)
        sqrt of eq. 21: the weighted RMS of R(p, dK) - R_opt over the offsets.
    """
    level_db = np.asarray(level_db, dtype=float)
    det = np.asarray(detected, dtype=bool) & np.isfinite(level_db)
    w = np.where(det, 1.0 / np.square(sd_db), 0.0)                     # (B, M)
    d0 = np.where(det, level_db - np.asarray(p0_db)[:, None] - gain_db, 0.0)
    # cost_c(r) = sum w (d0 - c - K)^2 = const(c) - 2 (w d0).K + 2 c w.K + w.K^2
    wk = w @ k_db                                                      # (B, R)
    base = w @ np.square(k_db) - 2.0 * ((w * d0) @ k_db)              # (B, R)
    r_opt = range_m[np.argmin(base, axis=1)]
    offsets = np.asarray(offsets_db, dtype=float)
    weights = np.full(len(offsets), 1.0 / len(offsets)) if weights is None else np.asarray(weights)
    var = np.zeros(len(level_db))
    for c, wc in zip(offsets, weights):
        if c == 0.0:
            rc = r_opt
        else:
            rc = range_m[np.argmin(base + 2.0 * c * wk, axis=1)]
        var += wc * np.square(rc - r_opt)
    none = ~det.any(axis=1)
    r_opt = np.where(none, np.nan, r_opt)
    return r_opt, np.where(none, np.nan, np.sqrt(var))


class KAtDepth:
    """K(r) of every class and band at a receiver depth, ``k_db`` corrected by the grid's TL.

    DESIGN.md: TL and K(r) are taken at the row's observer depth. The grid's ``k_db`` holds
    K = S - TL at the grid's observer depth (attribute ``observer_depth_m``); at depth d,

        K(d, r) = k_db(r) + TL(d_grid, r) - TL(d, r),

    with TL linear in depth over ``tl_db(class, band, depth, range)`` (so K(d_grid) equals
    ``k_db`` to float rounding). A grid without ``tl_db`` or without the attribute (a K-only
    grid of ``acoustics.build_k``) has K at one depth only and is used as is.

    Parameters
    ----------
    grid : xr.Dataset
    """

    def __init__(self, grid: xr.Dataset):
        self.k_db = np.asarray(grid["k_db"].transpose("class", "band", "range").values, dtype=float)
        obs = float(grid.attrs.get("observer_depth_m", math.nan))
        self.depth_axis_m = None
        self._cache: dict[float, np.ndarray] = {}
        if "tl_db" in grid and math.isfinite(obs):
            self.depth_axis_m = np.asarray(grid["depth"].values, dtype=float)
            self.tl_db = np.asarray(grid["tl_db"].transpose("class", "band", "depth", "range").values,
                                    dtype=float)                       # (C, M, D, R)
            self.grid_depth_m = obs
            self._tl_grid = self._tl(obs)

    def _tl(self, depth_m: float) -> np.ndarray:
        z = self.depth_axis_m
        if z.size == 1:
            return self.tl_db[:, :, 0]
        j = int(np.clip(np.searchsorted(z, depth_m, side="right") - 1, 0, z.size - 2))
        f = (depth_m - z[j]) / (z[j + 1] - z[j])
        return (1.0 - f) * self.tl_db[:, :, j] + f * self.tl_db[:, :, j + 1]

    def outside(self, depth_m) -> np.ndarray:
        """Mask of depths outside the grid's depth axis (all False for a K-only grid)."""
        d = np.asarray(depth_m, dtype=float)
        if self.depth_axis_m is None:
            return np.zeros(d.shape, dtype=bool)
        return ~((d >= self.depth_axis_m[0]) & (d <= self.depth_axis_m[-1]))

    def __call__(self, depth_m: float | None) -> np.ndarray:
        """K(r) at a receiver depth, dB, shape (C, M, R); None means the grid's observer depth.

        Raises
        ------
        MeasurementFileError
            The depth is outside the grid's depth axis.
        """
        if depth_m is None or self.depth_axis_m is None:
            return self.k_db
        d = float(depth_m)
        if d == self.grid_depth_m:
            return self.k_db
        if d not in self._cache:
            if self.outside(d):
                z = self.depth_axis_m
                raise MeasurementFileError(f"observer depth {d:g} m is outside the grid's depth "
                                           f"axis [{z[0]:g}, {z[-1]:g}] m")
            self._cache[d] = self.k_db + self._tl_grid - self._tl(d)
        return self._cache[d]
