"""A bank of depth hypotheses: each tracker runs once per hypothesis (K at that depth,
``Tables.at_target_depth``), and the depth's posterior, taken along the hypotheses' tracks from
the levels of every band (`tracker.depth.likelihood`), weighs them; each cycle reports the track
of the hypothesis picked by a rule (`TRACK_RULES`). The ML analysis (`tracker.mltma.depths`) and
the particle filters (``tmakit track --method rpf --target-depth unknown``) use it alike.

The depth's posterior is taken on the tables' own depth axis (every row inside the span), each
depth read along the track of the hypothesis nearest to it (`owners`), with the likelihood of
the levels of every band at once of `tracker.depth.errors` (the offset common to the bands, an
offset per band and the tables' K error along the track integrated out;
`tracker.depth.likelihood.TrackDepthLikelihood`), the prior uniform in ln(z + 1 m) over the span
(`tracker.depth.posterior`). A hypothesis's weight is the posterior mass of the depths it owns.

The track a depth is read along is each hypothesis's estimate at that cycle carried back over
its tack, and each earlier tack's last estimate over that tack (`tracker.depth.likelihood.line_back`):
the causal estimates of the first minutes are kilometres off, and every depth is judged on the
same cycles' levels. The posterior is taken at the first cycle, every `DEPTH_EVERY` cycles after and
at the last; each cycle's row of a class is the track of the hypothesis picked then, with
``depth_m`` the posterior median and ``depth_sd_m`` the posterior sd (held between the cycles it
is taken at); `DepthChoice` gives, after the last cycle, every hypothesis's weight, the 90 %
interval and the surface-or-submerged probabilities (docs/depth.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd

from acoustics.grid.face import Tables
from tracker.depth.likelihood import TrackDepthLikelihood, line_back
from tracker.depth.posterior import DepthPosterior, depth_grid_m, posterior
from tracker.measurements import Measurements

#: Depth hypotheses when none are given: this many over the class's span, evenly in ln(z + 10 m)
#: (closer near the surface, where K changes fastest with depth).
N_DEPTHS = 9
#: The offset of that spacing, m.
DEPTH_SPACING_OFFSET_M = 10.0
#: The interval `DepthChoice` gives: from this quantile to 1 less it.
INTERVAL_TAIL = 0.05
#: The depth posterior is taken every this many cycles (from the first, and at the last) ...
DEPTH_EVERY = 6
#: ... this many of those cycles' posteriors computed at once.
POSTERIOR_CHUNK = 8


@dataclass(frozen=True, slots=True, kw_only=True)
class DepthChoice:
    """The depth posterior of one class hypothesis after the last cycle.

    Attributes
    ----------
    cls_name : str
    depth_m : float
        The hypothesis of the largest weight, m.
    depths_m : tuple of float
        The hypotheses, m.
    weights : tuple of float
        Each hypothesis's posterior mass (the depths nearest to it), summing to 1.
    log_likelihood : tuple of float
        ln of each hypothesis's weight (up to a common constant: ln L over its depths).
    log_lr_next : float
        ln of the weight ratio of the best hypothesis to the next best.
    log_lr_class_depth : float or None
        ln of the ratio of the best to the class's own table depth (None when that depth is not
        a hypothesis).
    median_m : float
        Posterior median, m.
    interval_m : (float, float)
        The 90 % interval (5 % and 95 % quantiles), m.
    surface_probability, submerged_probability : float
        Posterior mass at most 15 m and at least 40 m deep (`tracker.depth.errors`).
    """

    cls_name: str
    depth_m: float
    depths_m: tuple[float, ...]
    weights: tuple[float, ...]
    log_likelihood: tuple[float, ...]
    log_lr_next: float
    log_lr_class_depth: float | None
    median_m: float
    interval_m: tuple[float, float]
    surface_probability: float
    submerged_probability: float


def depth_hypotheses_m(span_m: tuple[float, float], class_depth_m: float,
                       n: int = N_DEPTHS) -> np.ndarray:
    """``n`` depths over ``span_m`` (ends included), evenly in ln(z + `DEPTH_SPACING_OFFSET_M`),
    with the class's own depth when it lies inside the span."""
    lo, hi = span_m
    c = DEPTH_SPACING_OFFSET_M
    z = np.exp(np.linspace(math.log(lo + c), math.log(hi + c), n)) - c
    z[0], z[-1] = lo, hi
    if lo <= class_depth_m <= hi:
        z = np.unique(np.append(z, class_depth_m))
    return z


def owners(depth_m, hypotheses_m) -> np.ndarray:
    """The hypothesis nearest to each depth in ln(z + `DEPTH_SPACING_OFFSET_M`), (D,) indices."""
    c = DEPTH_SPACING_OFFSET_M
    u = np.log(np.maximum(np.asarray(depth_m, dtype=float), 0.0) + c)
    h = np.log(np.maximum(np.asarray(hypotheses_m, dtype=float), 0.0) + c)
    return np.argmin(np.abs(u[:, None] - h[None, :]), axis=1)


def depth_posterior(likelihood: TrackDepthLikelihood, hypotheses_m, span_m, t_s, range_m, bearing_deg,
                    level_db, snr_db, obs_x_m=None, obs_y_m=None) -> tuple[DepthPosterior, np.ndarray]:
    """The posterior over the tables' depths inside the span after each cycle, each depth along
    its owner's track.

    Parameters
    ----------
    likelihood : TrackDepthLikelihood
    hypotheses_m : array_like, shape (H,)
    span_m : (float, float)
    t_s : array_like, shape (T,)
        Cycle times, s.
    range_m, bearing_deg : array_like, shape (H, ..., T)
        Each hypothesis's track from the observer, m and deg.
    level_db, snr_db : array_like, shape (..., T, M)
    obs_x_m, obs_y_m : array_like, shape (T,), optional
        The observer's positions (the tables' fine errors grow away from their origin;
        ``TrackDepthLikelihood``).

    Returns
    -------
    post : DepthPosterior
        ``weight`` of shape (..., T, D).
    owner : ndarray of int, shape (D,)
        Each depth's hypothesis.
    """
    z = depth_grid_m(likelihood.tables.depth_m, span_m)
    own = owners(z, hypotheses_m)
    r = np.asarray(range_m, dtype=float)
    b = np.asarray(bearing_deg, dtype=float)
    ll = np.empty((z.size,) + r.shape[1:])
    for h in np.unique(own):
        rows = own == h
        ll[rows] = likelihood(z[rows], t_s, r[h], b[h], level_db, snr_db, obs_x_m, obs_y_m)
    return posterior(z, np.moveaxis(ll, 0, -1), span_m), own


def hypothesis_weights(post: DepthPosterior, owner, n_hypotheses: int) -> np.ndarray:
    """The posterior mass of each hypothesis's depths, (..., H)."""
    onehot = np.asarray(owner)[:, None] == np.arange(n_hypotheses)[None, :]
    return post.weight @ onehot.astype(float)


#: How a tracker picks, each cycle, the track it reports among its depth hypotheses': the one of
#: the largest posterior weight, or of the largest weight times the bearings' fit along its
#: track (`bearing_fit`: the levels' posterior leaves hypotheses it cannot tell apart whose
#: tracks differ, and the bearings, which it does not read, tell those tracks apart; measured
#: in docs/depth.md: the particle filters' bank by the bearings, the ML analysis by the weight).
TRACK_RULES = ("weight", "bearings")


def weigh_tracks(tables: Tables, ic: int, m: Measurements, tracks, hypotheses_m, span_m, *,
                 rule: str) -> tuple[pd.DataFrame, DepthChoice]:
    """One track from the depth hypotheses' (``tracks``, rows per cycle of ``m``): each cycle the
    row of the hypothesis picked by ``rule`` (`TRACK_RULES`) when the posterior was last taken
    (`posterior_along_tracks`), with ``depth_m`` and ``depth_sd_m`` the posterior's median and
    sd then; and the final posterior as a `DepthChoice`."""
    _check_rule(rule)
    z = np.asarray(hypotheses_m, dtype=float)
    cls = tables.classes[ic]
    post, own, held, fit = posterior_along_tracks(tables, ic, m, tracks, z, span_m)
    w = hypothesis_weights(post, own, z.size)                           # (C, H)
    best = picked_hypothesis(w, fit, rule)[held]
    rows = pd.concat([tracks[best[i]].iloc[[i]] for i in range(len(m))], ignore_index=True)
    rows["depth_m"] = post.quantile(0.5)[held]
    rows["depth_sd_m"] = post.sd()[held]
    last = w[-1]
    with np.errstate(divide="ignore"):
        lw = np.log(last)
    order = np.argsort(last)[::-1]
    own_depth = np.flatnonzero(np.isclose(z, cls.depth_m))
    final = post.at_cycle(post.weight[-1])
    surf, sub = final.surface_probability()
    choice = DepthChoice(
        cls_name=cls.name, depth_m=float(z[order[0]]), depths_m=tuple(float(v) for v in z),
        weights=tuple(float(v) for v in last), log_likelihood=tuple(float(v) for v in lw),
        log_lr_next=float(lw[order[0]] - lw[order[1]]) if z.size > 1 else math.inf,
        log_lr_class_depth=float(lw[order[0]] - lw[own_depth[0]]) if own_depth.size else None,
        median_m=float(final.quantile(0.5)),
        interval_m=(float(final.quantile(INTERVAL_TAIL)), float(final.quantile(1.0 - INTERVAL_TAIL))),
        surface_probability=float(surf), submerged_probability=float(sub))
    return rows, choice


def _check_rule(rule: str) -> None:
    if rule not in TRACK_RULES:
        raise ValueError(f"rule must be one of {', '.join(TRACK_RULES)}, got {rule!r}")


def picked_hypothesis(weights, fit, rule: str) -> np.ndarray:
    """The hypothesis each rule of `TRACK_RULES` picks from the posterior weights (..., H) and the
    bearings' fit (..., H, `bearing_fit`): the largest weight, or weight times the fit, (...)."""
    _check_rule(rule)
    with np.errstate(divide="ignore"):
        score = np.log(weights) + (fit if rule == "bearings" else 0.0)
    return np.argmax(score, axis=-1)


def bearing_fit(measured_deg, bearing_z) -> np.ndarray:
    """ln of the measured bearings' (..., T) likelihood along each hypothesis's track (bearings
    (H, ..., T)) up to each cycle, their sd unknown and common to the hypotheses (concentrated:
    -n/2 ln of the mean squared residual; a cycle without a bearing counts for none), (..., T, H)."""
    resid = np.radians(np.mod(np.asarray(bearing_z, dtype=float) - np.asarray(measured_deg, dtype=float)[None]
                              + 180.0, 360.0) - 180.0)
    ok = np.isfinite(resid)
    n = np.cumsum(ok, axis=-1)
    mean_sq = np.cumsum(np.where(ok, resid * resid, 0.0), axis=-1) / np.maximum(n, 1)
    return np.moveaxis(-0.5 * n * np.log(np.maximum(mean_sq, 1e-300)), 0, -1)


def posterior_along_tracks(tables: Tables, ic: int, m: Measurements, tracks, hypotheses_m,
                           span_m) -> tuple[DepthPosterior, np.ndarray, np.ndarray, np.ndarray]:
    """The depth posterior of class ``ic`` from the levels of every band of ``m``, taken at the
    first cycle, every `DEPTH_EVERY` cycles after and at the last, each time along the tracks as
    known then (`_carried_back`), each depth along its hypothesis's track (`depth_posterior`).

    Parameters
    ----------
    tables : Tables
    ic : int
    m : Measurements
        The cycles the tracks have rows for.
    tracks : list of pandas.DataFrame
        One per hypothesis (``x_m``, ``y_m``, ``course_deg``, ``speed_mps``, ``tack`` per cycle).
    hypotheses_m : array_like, shape (H,)
    span_m : (float, float)

    Returns
    -------
    post : DepthPosterior
        ``weight`` of shape (C, D): the posterior as taken at each of the C cycles.
    owner : ndarray of int, shape (D,)
        Each depth's hypothesis.
    held : ndarray of int, shape (T,)
        For each cycle, the row of ``post`` last taken at or before it.
    fit : ndarray, shape (C, H)
        The bearings' fit along each hypothesis's track as known then (`bearing_fit`).
    """
    n_t = len(m)
    at = np.unique(np.append(np.arange(0, n_t, DEPTH_EVERY), n_t - 1))  # from the first cycle on
    r, b = _carried_back(tracks, m, at)                                 # (H, C, T)
    like = TrackDepthLikelihood(tables, ic, m.band_names, span_m)
    level, snr = np.asarray(m.level_db, dtype=float), np.asarray(m.snr_db, dtype=float)
    weights = []
    for c0 in range(0, at.size, POSTERIOR_CHUNK):  # a few at a time: memory grows with depths x cycles
        part = slice(c0, c0 + POSTERIOR_CHUNK)
        post, own = depth_posterior(like, hypotheses_m, span_m, m.t_s, r[:, part], b[:, part], level, snr,
                                    m.obs_x_m, m.obs_y_m)
        weights.append(post.weight[:, -1])                              # each its own cycle's
    held = np.searchsorted(at, np.arange(n_t), side="right") - 1
    measured = np.broadcast_to(np.asarray(m.bearing_deg, dtype=float), (at.size, n_t))
    fit = bearing_fit(measured, b)[np.arange(at.size), at]                # (C, H)
    return post.at_cycle(np.concatenate(weights)), own, held, fit


def _carried_back(tracks, m: Measurements, at) -> tuple[np.ndarray, np.ndarray]:
    """Range and bearing from the observer of each hypothesis's track as known at each cycle of
    ``at``: each of its tacks the estimate at that tack's last cycle (or at that cycle) carried
    back over the tack (NaN after that cycle), (H, C, T) each. Every hypothesis has a track over
    every cycle: its depths' likelihoods are compared over the same levels (a hypothesis that
    declared a manoeuvre is not judged on its last tack's levels alone)."""
    n_t = len(m)
    r = np.full((len(tracks), len(at), n_t), np.nan)
    b = np.full(r.shape, np.nan)
    t = np.asarray(m.t_s, dtype=float)
    for h, trk in enumerate(tracks):
        course = np.radians(trk["course_deg"].to_numpy())
        speed = trk["speed_mps"].to_numpy()
        px, py = trk["x_m"].to_numpy(), trk["y_m"].to_numpy()
        vx, vy = speed * np.sin(course), speed * np.cos(course)
        tack = trk["tack"].to_numpy()
        firsts = np.flatnonzero(np.diff(tack, prepend=np.nan) != 0)      # each tack's first cycle
        for c, i in enumerate(at):
            x, y = np.empty(i + 1), np.empty(i + 1)
            starts = firsts[firsts <= i]
            for s0, e0 in zip(starts, np.append(starts[1:] - 1, i)):
                part = slice(s0, e0 + 1)
                x[part], y[part] = line_back(t[part], px[part], py[part], vx[part], vy[part])
            dx, dy = x - m.obs_x_m[:i + 1], y - m.obs_y_m[:i + 1]
            r[h, c, :i + 1] = np.hypot(dx, dy)
            b[h, c, :i + 1] = np.mod(np.degrees(np.arctan2(dx, dy)), 360.0)
    return r, b
