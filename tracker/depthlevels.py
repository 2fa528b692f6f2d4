"""ln L of depth from the levels of every band along a track (`tracker.depthpost`'s model),
read from the tables: `TrackDepthLikelihood`.

For each band the table of K against target depth and range (``Tables.target_depth_k``,
per radial) is averaged over the range uncertainty with its spread (`tracker.kstructure`), on
the rows of the depth axis the span needs, once. Along a track (the target's estimated
positions, the observer's) the residuals W - (P0 + K_s + G) and the variances eq. 11's
sigma_dW^2 + V_s at each depth asked for go to `tracker.depthpost.log_marginal`.
"""

from __future__ import annotations

import numpy as np

from acoustics.grid.targetdepth import TargetDepthK
from tracker.depthpost import LevelErrors, log_marginal
from tracker.kstructure import RangeSmoothing, smoothed_k
from tracker.mltma import measurement_sd


class TrackDepthLikelihood:
    """ln L(z) of a class's band levels along tracks, K from the tables at every depth.

    Parameters
    ----------
    tables : Tables
        Tables that serve any target depth (``serves_target_depth``).
    ic : int
        The class.
    band_names : sequence of str
        The bands whose levels are given, in the levels' column order.
    span_m : (float, float)
        The depths that will be asked for, m (rows of the depth axis beyond them are dropped).
    errors : LevelErrors, optional
        Default `LevelErrors.of_class`.
    smoothing : RangeSmoothing, optional
        Default `RangeSmoothing()`.
    """

    def __init__(self, tables, ic: int, band_names, span_m, *, errors: LevelErrors | None = None,
                 smoothing: RangeSmoothing | None = None):
        self.tables = tables
        self.ic = int(ic)
        self.cls = tables.classes[ic]
        self.errors = errors or LevelErrors.of_class(self.cls)
        self.smoothing = smoothing or RangeSmoothing()
        self.bands = [tables.band_index(b) for b in band_names]
        sonar = tables.area.sonar
        self._bw = np.asarray(tables.bandwidth_hz)[self.bands]
        self._q_thr = measurement_sd.threshold_snr(sonar.detection_threshold, self._bw,
                                                   sonar.integration_time_s)
        self._t_int = sonar.integration_time_s
        self._base_db = float(self.cls.noise_mean_db) + sonar.receiver_gain_db
        self._mean, self._var = [], []
        for ib in self.bands:
            tk = tables.target_depth_k(ic, ib)
            z = np.asarray(tk.depth_m, dtype=float)
            lo = max(int(np.searchsorted(z, span_m[0], side="right")) - 2, 0)
            hi = min(int(np.searchsorted(z, span_m[1], side="left")) + 2, z.size)
            k = np.asarray(tk.k_db, dtype=float)[:, lo:hi]
            mean, var = smoothed_k(k, tk.range_m, self.smoothing)
            self._mean.append(TargetDepthK(bearing_deg=tk.bearing_deg, depth_m=z[lo:hi],
                                           range_m=tk.range_m, k_db=mean))
            self._var.append(TargetDepthK(bearing_deg=tk.bearing_deg, depth_m=z[lo:hi],
                                          range_m=tk.range_m, k_db=var))

    def level_sd_db(self, snr_db) -> np.ndarray:
        """eq. 11's sigma_dW from the bands' SNR (..., M), dB."""
        snr = np.asarray(snr_db, dtype=float)
        flat = snr.reshape(-1, snr.shape[-1])
        sd = measurement_sd.level_sd_from_snr_db(flat, self._q_thr, self._bw, self._t_int)
        return sd.reshape(snr.shape)

    def __call__(self, depth_m, range_m, bearing_deg, level_db, snr_db) -> np.ndarray:
        """ln L at each depth after each cycle.

        Parameters
        ----------
        depth_m : array_like, shape (D,)
        range_m, bearing_deg : array_like, shape (..., T)
            The track's range and bearing from the observer at each cycle, m and deg.
        level_db, snr_db : array_like, shape (..., T, M)
            The measured levels (NaN: none) and SNR, dB.

        Returns
        -------
        ndarray, shape (D, ..., T)
        """
        z = np.asarray(depth_m, dtype=float).reshape((-1,) + (1,) * np.ndim(range_m))
        r = np.asarray(range_m, dtype=float)[None]
        b = np.asarray(bearing_deg, dtype=float)[None]
        level = np.asarray(level_db, dtype=float)[None]
        sd = self.level_sd_db(snr_db)[None]
        k = np.stack([m.at(z, r, b) for m in self._mean], axis=-1)         # (D, ..., T, M)
        v = np.stack([m.at(z, r, b) for m in self._var], axis=-1)
        resid = level - (self._base_db + k)
        var = sd ** 2 + np.where(np.isfinite(v), v, 0.0)
        return log_marginal(resid, var, np.broadcast_to(r, resid.shape[:-1]), self.errors)
