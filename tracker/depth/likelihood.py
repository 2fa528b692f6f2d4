"""ln L of depth from the levels of every band along a track (`tracker.depth.errors`'s model),
read from the tables: `TrackDepthLikelihood`.

For each band the table of K against target depth and range (``Tables.target_depth_k``,
per radial) is taken on the rows of the depth axis the span needs and averaged over the track's
range uncertainty (`tracker.depth.kstructure`, `K_SMOOTHING`), once. Along a track (the target's
estimated positions from the observer) the residuals W - (P0 + K_s + G) and eq. 11's
sigma_dW^2 at each depth asked for go to `tracker.depth.errors.log_marginal`.

The track should be a smoothed one: the final estimate of a tracker's motion carried back over
the cycles of its tack (`line_back`), not each cycle's causal estimate, whose early cycles are
kilometres off while the analysis converges (measured in docs/depth.md). The likelihood is
integrated over the track's range scale s (every relative position times s, bearings kept), s
log-normal about 1 with sd ``range_scale_sd`` (default `RANGE_SCALE_SD`), on
`RANGE_SCALE_NODES` Gauss-Hermite nodes: L(z) = sum_s p(s) L(z | s x track).
"""

from __future__ import annotations

import numpy as np

from acoustics.grid.targetdepth import TargetDepthK
from tracker.depth.errors import LevelErrors, log_marginal
from tracker.depth.kstructure import RangeSmoothing, smoothed_k
from tracker.mltma import measurement_sd

#: The range uncertainty K is averaged over along an estimated track.
K_SMOOTHING = RangeSmoothing(fraction=0.07, floor_m=100.0)
#: sd of ln(range scale) the likelihood is integrated over by default: the tracks a depth
#: posterior reads are off in range by a scale (the final estimate carried back), RMS 0.24-0.31
#: in ln over the depth study's ML hypotheses and bank (docs/results/depth/depth.json,
#: ``track_range_scale_ln_rms``, ``ml_unknown*`` and ``rpf_bank*``) before each band's own K
#: error was in the trackers' model, 0.18-0.26 since; this is below their median, and the table's
#: K read at a scaled range also takes up part of the tables' error along range away from their
#: origin (0.17, under the least of them, cost the depth intervals at 6 m: tests/tools/studies/test_depth.py).
RANGE_SCALE_SD = 0.2
#: Nodes of the integral over the range scale (Gauss-Hermite: exact for a likelihood
#: polynomial in ln s up to degree 2n - 1).
RANGE_SCALE_NODES = 5


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
        sd of ln(range scale) the likelihood is integrated over (default `RANGE_SCALE_SD`; 0: the
        track as it is).
    smoothing : RangeSmoothing, optional
        The range uncertainty K is averaged over (default `K_SMOOTHING`).
    """

    def __init__(self, tables, ic: int, band_names, span_m, *, errors: LevelErrors | None = None,
                 range_scale_sd: float = RANGE_SCALE_SD, smoothing: RangeSmoothing | None = None):
        self.tables = tables
        self.ic = int(ic)
        self.cls = tables.classes[ic]
        self.errors = errors or LevelErrors.of_class(self.cls)
        self.smoothing = K_SMOOTHING if smoothing is None else smoothing
        if not (np.isfinite(range_scale_sd) and range_scale_sd >= 0.0):
            raise ValueError(f"range_scale_sd must be >= 0, got {range_scale_sd}")
        if range_scale_sd > 0.0:
            u, w = np.polynomial.hermite_e.hermegauss(RANGE_SCALE_NODES)   # for the weight e^(-u^2/2)
            self.scales = np.exp(range_scale_sd * u)
            self.log_scale_weight = np.log(w / w.sum())
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
            errors grow with its distance from there (`Tables.distance_from_origin_m`; default: at the origin).

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
        away = None if obs_x_m is None else self.tables.distance_from_origin_m(obs_x_m, obs_y_m)
        ll = log_marginal(resid, sd ** 2, t_s, self.errors, away)             # (D, S, ..., T)
        # a depth the tables have no K for where a level was measured and the track has a position
        # (no water there: below the bottom) is ruled out from that cycle on, not spared the
        # cycle's term, which would make it the most likely of all; a cycle before the track
        # begins (NaN range) says nothing, whatever the depth
        lost = (np.isfinite(level) & ~np.isfinite(k)).any(axis=-1) & np.isfinite(r)
        ll = np.where(np.logical_or.accumulate(lost, axis=-1), -np.inf, ll)
        lw = self.log_scale_weight.reshape((1, -1) + (1,) * (ll.ndim - 2)) + ll
        top = lw.max(axis=1, keepdims=True)
        top = np.where(np.isfinite(top), top, 0.0)
        with np.errstate(divide="ignore"):
            return (top + np.log(np.exp(lw - top).sum(axis=1, keepdims=True)))[:, 0]
