"""ln L of depth from the levels of every band along a track (`tracker.depthpost`'s model),
read from the tables: `TrackDepthLikelihood`.

For each band the table of K against target depth and range (``Tables.target_depth_k``,
per radial) is taken on the rows of the depth axis the span needs and averaged over the track's
range uncertainty (`tracker.kstructure`, `K_SMOOTHING`), once. Along a track (the target's
estimated positions from the observer) the residuals W - (P0 + K_s + G) and eq. 11's
sigma_dW^2 at each depth asked for go to `tracker.depthpost.log_marginal`.

The track should be a smoothed one: the final estimate of a tracker's motion carried back over
the cycles of its tack (`line_back`), not each cycle's causal estimate, whose early cycles are
kilometres off while the analysis converges (measured in docs/depth.md). Optionally the
likelihood is integrated over the track's range scale s (every relative position times s,
bearings kept), s log-normal about 1 with sd ``range_scale_sd``, on `RANGE_SCALE_NODES` nodes
over +-2.5 sd: L(z) = sum_s p(s) L(z | s x track).
"""

from __future__ import annotations

import numpy as np

from acoustics.grid.targetdepth import TargetDepthK
from tracker.depthpost import LevelErrors, log_marginal
from tracker.kstructure import RangeSmoothing, smoothed_k
from tracker.mltma import measurement_sd

#: The range uncertainty K is averaged over along an estimated track.
K_SMOOTHING = RangeSmoothing(fraction=0.07, floor_m=100.0)
#: Nodes of the integral over the range scale.
RANGE_SCALE_NODES = 9


def line_back(t_s, x_m, y_m, vx_mps, vy_mps, start: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A track's positions at every cycle from its last estimate: the last position less the last
    velocity times the time to the end, from cycle ``start`` on (NaN before), (..., T) each."""
    t = np.asarray(t_s, dtype=float)
    back = (t[-1] - t)
    x = np.asarray(x_m, dtype=float)[..., -1:] - np.asarray(vx_mps, dtype=float)[..., -1:] * back
    y = np.asarray(y_m, dtype=float)[..., -1:] - np.asarray(vy_mps, dtype=float)[..., -1:] * back
    x[..., :start] = np.nan
    y[..., :start] = np.nan
    return x, y


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
    range_scale_sd : float
        sd of ln(range scale) the likelihood is integrated over (default 0: the track as it is).
    smoothing : RangeSmoothing, optional
        The range uncertainty K is averaged over (default `K_SMOOTHING`).
    """

    def __init__(self, tables, ic: int, band_names, span_m, *, errors: LevelErrors | None = None,
                 range_scale_sd: float = 0.0, smoothing: RangeSmoothing | None = None):
        self.tables = tables
        self.ic = int(ic)
        self.cls = tables.classes[ic]
        self.errors = errors or LevelErrors.of_class(self.cls)
        self.smoothing = K_SMOOTHING if smoothing is None else smoothing
        if range_scale_sd > 0.0:
            u = np.linspace(-2.5, 2.5, RANGE_SCALE_NODES)
            self.scales = np.exp(range_scale_sd * u)
            lw = -0.5 * u * u
            self.log_scale_weight = lw - np.log(np.exp(lw).sum())
        else:
            self.scales, self.log_scale_weight = np.ones(1), np.zeros(1)
        self.bands = [tables.band_index(b) for b in band_names]
        sonar = tables.area.sonar
        self._bw = np.asarray(tables.bandwidth_hz)[self.bands]
        self._q_thr = measurement_sd.threshold_snr(sonar.detection_threshold, self._bw,
                                                   sonar.integration_time_s)
        self._t_int = sonar.integration_time_s
        self._base_db = float(self.cls.noise_mean_db) + sonar.receiver_gain_db
        self._mean = []
        for ib in self.bands:
            tk = tables.target_depth_k(ic, ib)
            z = np.asarray(tk.depth_m, dtype=float)
            lo = max(int(np.searchsorted(z, span_m[0], side="right")) - 2, 0)
            hi = min(int(np.searchsorted(z, span_m[1], side="left")) + 2, z.size)
            k = np.asarray(tk.k_db, dtype=float)[:, lo:hi]
            mean, _ = smoothed_k(k, tk.range_m, self.smoothing)
            self._mean.append(TargetDepthK(bearing_deg=tk.bearing_deg, depth_m=z[lo:hi],
                                           range_m=tk.range_m, k_db=mean))

    def level_sd_db(self, snr_db) -> np.ndarray:
        """eq. 11's sigma_dW from the bands' SNR (..., M), dB."""
        snr = np.asarray(snr_db, dtype=float)
        flat = snr.reshape(-1, snr.shape[-1])
        sd = measurement_sd.level_sd_from_snr_db(flat, self._q_thr, self._bw, self._t_int)
        return sd.reshape(snr.shape)

    def displacement_m(self, obs_x_m, obs_y_m) -> np.ndarray | None:
        """The observer's distance at each cycle from where the tables were computed, m (None
        for tables that hold everywhere: their fine errors do not grow)."""
        x, y = np.asarray(obs_x_m, dtype=float), np.asarray(obs_y_m, dtype=float)
        if self.tables.observer_offset(x, y) is None:
            return None
        return np.hypot(x, y)

    def __call__(self, depth_m, t_s, range_m, bearing_deg, level_db, snr_db, obs_x_m=None,
                 obs_y_m=None) -> np.ndarray:
        """ln L at each depth after each cycle.

        Parameters
        ----------
        depth_m : array_like, shape (D,)
        t_s : array_like, shape (T,)
            Cycle times, s.
        range_m, bearing_deg : array_like, shape (..., T)
            The track's range and bearing from the observer at each cycle, m and deg.
        level_db, snr_db : array_like, shape (..., T, M)
            The measured levels (NaN: none) and SNR, dB.
        obs_x_m, obs_y_m : array_like, shape (T,), optional
            The observer's position, m east and north of the tables' origin: the tables' fine
            errors grow with its distance from there (`displacement_m`; default: at the origin).

        Returns
        -------
        ndarray, shape (D, ..., T)
        """
        nd = np.ndim(range_m)
        z = np.asarray(depth_m, dtype=float).reshape((-1, 1) + (1,) * nd)
        scale = self.scales.reshape((1, -1) + (1,) * nd)
        r = scale * np.asarray(range_m, dtype=float)[None, None]                # (1, S, ..., T)
        b = np.asarray(bearing_deg, dtype=float)[None, None]
        level = np.asarray(level_db, dtype=float)[None, None]
        sd = self.level_sd_db(snr_db)[None, None]
        k = np.stack([m.at(z, r, b) for m in self._mean], axis=-1)             # (D, S, ..., T, M)
        resid = level - (self._base_db + k)
        away = None if obs_x_m is None else self.displacement_m(obs_x_m, obs_y_m)
        ll = log_marginal(resid, sd ** 2, t_s, self.errors, away)             # (D, S, ..., T)
        lw = self.log_scale_weight.reshape((1, -1) + (1,) * (ll.ndim - 2)) + ll
        top = lw.max(axis=1, keepdims=True)
        return (top + np.log(np.exp(lw - top).sum(axis=1, keepdims=True)))[:, 0]
