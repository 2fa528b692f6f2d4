"""The ML analysis with an unknown target depth: class hypotheses times depth hypotheses.

Not in Grinenkov & Mashoshin (their classes radiate from one depth each). For each depth
hypothesis z the whole analysis runs on the tables with K at z
(``Tables.at_target_depth``); the hypotheses are then weighed by the likelihood of the
band levels along each one's own track:

    e_i = W_i - (P0 + K_z(r_i, bearing_i) + G)         (eq. 12; r_i the track's range at cycle i)
    ln L_z = -1/2 [ sum_i (e_i - b)^2 / s_i^2 + b^2 / s_b^2 ],  maximised over b,

s_i the level sd of eq. 11 from the cycle's SNR, b the offset common to the whole track (P0 and
the K error of eq. 31 do not change from cycle to cycle: s_b^2 = sd(P0)^2 + sd(dK)^2). Taken
over the cycles so far this is a profile likelihood over the motion and the offset; its
maximum is each cycle's depth estimate, and the likelihood ratio of the best hypothesis to the
next and to the class's own depth says how sure it is. The source-level offset b is what the
levels cannot tell from depth: a depth whose K differs from the truth by a constant over the
ranges crossed is explained as well by an offset (see docs/depth.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from acoustics.grid.face import Tables
from tracker.measurements import Measurements
from tracker.mltma import measurement_sd
from tracker.mltma.params import MLParams

#: Depth hypotheses when none are given: this many, evenly over the class's span.
N_DEPTHS = 8


@dataclass(frozen=True, slots=True, kw_only=True)
class DepthChoice:
    """The most likely depth of one class hypothesis after the last cycle.

    Attributes
    ----------
    cls_name : str
    depth_m : float
        The most likely depth hypothesis, m.
    depths_m : tuple of float
        The hypotheses, m.
    log_likelihood : tuple of float
        ln L of each, at the last cycle.
    log_lr_next : float
        ln of the likelihood ratio of the best hypothesis to the next best.
    log_lr_class_depth : float or None
        ln of the ratio of the best to the class's own table depth (None when that depth is not
        a hypothesis).
    """

    cls_name: str
    depth_m: float
    depths_m: tuple[float, ...]
    log_likelihood: tuple[float, ...]
    log_lr_next: float
    log_lr_class_depth: float | None


def depth_hypotheses_m(span_m: tuple[float, float], class_depth_m: float,
                       n: int = N_DEPTHS) -> np.ndarray:
    """``n`` depths evenly over ``span_m`` (ends included), with the class's own depth when it
    lies inside the span."""
    lo, hi = span_m
    z = np.linspace(lo, hi, n)
    if lo <= class_depth_m <= hi:
        z = np.unique(np.append(z, class_depth_m))
    return z


def level_log_likelihood(track: pd.DataFrame, m: Measurements, tables: Tables, ic: int
                         ) -> np.ndarray:
    """ln L of the levels along one hypothesis's track at each cycle (cumulative), (T,).

    ``tables`` give K at the hypothesis's depth; ``track`` is the class's rows (one per cycle of
    ``m``, same order). Bands without a level do not count.
    """
    cls = tables.classes[ic]
    sonar = tables.area.sonar
    x = track["x_m"].to_numpy() - m.obs_x_m
    y = track["y_m"].to_numpy() - m.obs_y_m
    r = np.hypot(x, y)
    bearing = np.mod(np.degrees(np.arctan2(x, y)), 360.0)
    k = tables.k_at(ic, r, bearing_deg=bearing)                               # (T, M)
    bands = [tables.band_index(b) for b in m.band_names]
    k = k[:, bands]
    pred = cls.noise_mean_db + k + sonar.receiver_gain_db
    q_thr = measurement_sd.threshold_snr(sonar.detection_threshold, tables.bandwidth_hz[bands],
                                         sonar.integration_time_s)
    sd = measurement_sd.level_sd_from_snr_db(np.asarray(m.snr_db, dtype=float), q_thr,
                                             tables.bandwidth_hz[bands], sonar.integration_time_s)
    e = np.asarray(m.level_db, dtype=float) - pred
    use = np.isfinite(e) & np.isfinite(sd) & (sd > 0)
    inv = np.where(use, 1.0 / np.where(use, sd, 1.0) ** 2, 0.0)
    e = np.where(use, e, 0.0)
    s1 = np.cumsum(inv.sum(axis=1))
    se = np.cumsum((e * inv).sum(axis=1))
    see = np.cumsum((e * e * inv).sum(axis=1))
    prior = 1.0 / max(cls.noise_sd_db ** 2 + cls.k_error_sd_db ** 2, 1e-6)
    b = se / (s1 + prior)
    return -0.5 * (see - 2.0 * b * se + b * b * s1 + b * b * prior)


def track_depths(tables: Tables, m: Measurements, *, cls_name: str | None = None,
                 band: str | None = None, params: MLParams | None = None,
                 depths_m=None) -> tuple[pd.DataFrame, list[DepthChoice]]:
    """The ML analysis over class x depth hypotheses; one row per cycle per class.

    Each cycle's row of a class is the track of its most likely depth so far, with
    ``depth_m`` that depth and ``depth_sd_m`` the sd of the hypotheses weighted by their
    likelihoods.

    Parameters
    ----------
    tables : Tables
        Must serve K at any target depth (``serves_target_depth``).
    m : Measurements
        Bearings and levels (cycles without a bearing dropped, as in
        ``tracker.mltma.track_measurements``).
    cls_name, band, params
        As ``tracker.mltma.track_measurements``.
    depths_m : array_like, optional
        The depth hypotheses, m; default `depth_hypotheses_m` of each class's span
        (``Tables.target_depth_span_m``).

    Returns
    -------
    rows : DataFrame
        Track columns (``tracker.trackfile.TRACK_COLUMNS``).
    choices : list of DepthChoice
        Per class, the most likely depth after the last cycle.
    """
    from tracker.mltma.tracker import track_measurements

    names = tables.class_names if cls_name is None else (cls_name,)
    good = m.take(np.flatnonzero(np.isfinite(m.bearing_deg)))
    if band is not None:
        j = good.band_names.index(band)
        good = Measurements(source=good.source, t_s=good.t_s, obs_x_m=good.obs_x_m,
                            obs_y_m=good.obs_y_m, obs_depth_m=good.obs_depth_m,
                            bearing_deg=good.bearing_deg, bearing_sigma_deg=good.bearing_sigma_deg,
                            band_names=(band,), level_db=good.level_db[:, j:j + 1],
                            snr_db=good.snr_db[:, j:j + 1])
    frames, choices = [], []
    for name in names:
        ic = tables.class_index(name)
        cls = tables.classes[ic]
        z = (np.asarray(depths_m, dtype=float) if depths_m is not None
             else depth_hypotheses_m(tables.target_depth_span_m(ic), cls.depth_m))
        tracks, loglik = [], []
        for depth in z:
            view = tables.at_target_depth(float(depth))
            trk = track_measurements(view, good, cls_name=name, band=None, params=params)
            tracks.append(trk.reset_index(drop=True))
            loglik.append(level_log_likelihood(trk, good, view, ic))
        ll = np.array(loglik)                                             # (Z, T)
        best = np.argmax(ll, axis=0)                                      # (T,)
        w = np.exp(ll - ll.max(axis=0))
        w /= w.sum(axis=0)
        zhat = z[best]
        sd = np.sqrt(np.sum(w * (z[:, None] - zhat[None, :]) ** 2, axis=0))
        rows = pd.concat([tracks[best[i]].iloc[[i]] for i in range(best.size)], ignore_index=True)
        rows["depth_m"] = zhat
        rows["depth_sd_m"] = sd
        frames.append(rows)
        last = ll[:, -1]
        order = np.argsort(last)[::-1]
        own = np.flatnonzero(np.isclose(z, cls.depth_m))
        choices.append(DepthChoice(
            cls_name=name, depth_m=float(z[order[0]]), depths_m=tuple(float(v) for v in z),
            log_likelihood=tuple(float(v) for v in last),
            log_lr_next=float(last[order[0]] - last[order[1]]) if z.size > 1 else math.inf,
            log_lr_class_depth=float(last[order[0]] - last[own[0]]) if own.size else None))
    return pd.concat(frames, ignore_index=True), choices
