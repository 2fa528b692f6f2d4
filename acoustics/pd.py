"""Probability of detection: P_D = Phi(SE / sigma), its detection ranges, and the cumulative P_D
of independent looks with a persistent offset (DESIGN.md "Detection planning").

A band is detected where its indicator SNR reaches the sonar's threshold (``acoustics.detection``),
that is where K(r) reaches the K the band needs at the class's mean level. The signal excess

    SE = K(r) - K_needed,   dB,

is that margin (the same as 10 lg q - 10 lg q_needed: 10 lg q is linear in K). The level a
target gives scatters about the class's mean, Gaussian in dB with sd sigma (the class's source
level and K's error: ``acoustics.grid.detectionsigma``), so one look detects the band with

    P_D = Phi(SE / sigma),

1/2 exactly where SE = 0, the detection map's edge; sigma -> 0 gives the map's step. "Any band"
is 1 - prod over bands (1 - P_band): the bands are taken as independent of each other (their
offsets too); where they share one offset (the source level is one number) the truth lies
between that and the best band's P_D, the bound of fully correlated bands.

The detection range at a level p is the largest range of the table where P_D >= p (the detection
map's rule, ``acoustics.detection.farthest_m``): P_D >= p where SE >= sigma Phi^-1(p). A range where P_D still
reaches p at the table's last range is "beyond the table": no range is given for it.

Along a track, the level's offset does not draw anew at every look: the source level of one
target and K's offset hold (DESIGN.md "K's error and stated uncertainty"). With the persistent
part b_i = s_i z (one standard normal z per track, scaled by each look's persistent sd s_i) and a
part w_i drawn independently at every look (one look per integration time),

    P_cum(t) = E_z[1 - prod_{i: t_i <= t} (1 - Phi((SE_i + s_i z) / w_i))],

integrated over z here (`cumulative_pd`); a look with w_i = 0 is a step in z, integrated exactly.
No scipy at run time: Phi is ``math.erfc``, Phi^-1 the standard library's ``NormalDist``.
"""

from __future__ import annotations

import math
from statistics import NormalDist

import numpy as np

#: The P_D levels whose ranges a planner reads (LYBIN and the like report the 0.5 one).
PD_LEVELS = (0.9, 0.5, 0.1)
#: The standard normal offsets the z integral of `cumulative_pd` covers, +-.
Z_SPAN = 8.5
#: Steps of that integral: at most this spacing, and a quarter of the narrowest per-look width
#: (w_i / s_i) of a look, within `Z_MAX_NODES` nodes.
Z_STEP = 0.01
Z_MAX_NODES = 200_001

_erfc = np.frompyfunc(math.erfc, 1, 1)


def normal_cdf(x) -> np.ndarray:
    """Phi(x), the standard normal distribution function, elementwise (NaN stays NaN)."""
    a = np.asarray(x, dtype=float)
    return 0.5 * np.asarray(_erfc(-a / math.sqrt(2.0)), dtype=float).reshape(a.shape)


def normal_quantile(p: float) -> float:
    """Phi^-1(p) for 0 < p < 1 (0 exactly at p = 1/2)."""
    return NormalDist().inv_cdf(p)


def pd_of_excess(excess_db, sigma_db) -> np.ndarray:
    """P_D = Phi(SE / sigma) elementwise; sigma 0 gives the step (1 where SE >= 0); NaN SE (no K,
    beyond land) gives 0.

    Parameters
    ----------
    excess_db : array_like
        Signal excess SE = K(r) - K_needed, dB.
    sigma_db : array_like
        sd of the level about the class's mean, dB, >= 0; broadcasts against ``excess_db``.
    """
    se, sd = np.broadcast_arrays(np.asarray(excess_db, dtype=float), np.asarray(sigma_db, dtype=float))
    with np.errstate(divide="ignore", invalid="ignore"):
        u = np.where(sd > 0, se / np.where(sd > 0, sd, 1.0), np.where(se >= 0, np.inf, -np.inf))
    return np.where(np.isnan(se), 0.0, normal_cdf(np.nan_to_num(u, nan=-np.inf)))


def any_band(pd, axis: int = 0) -> np.ndarray:
    """P_D of any band, 1 - prod(1 - P_band) over ``axis``: the bands independent (module docstring)."""
    return 1.0 - np.prod(1.0 - np.asarray(pd, dtype=float), axis=axis)


def cumulative_pd(excess_db, persistent_db, per_look_db) -> np.ndarray:
    """The probability that at least one look has detected by each look (module docstring).

    Parameters
    ----------
    excess_db : array_like, shape (T,)
        Signal excess at each look, dB; NaN (no K: beyond land) never detects.
    persistent_db : array_like, shape (T,) or scalar
        sd of the part of the level that holds along the track (one draw per track), dB, >= 0.
    per_look_db : array_like, shape (T,) or scalar
        sd of the part drawn anew at every look, independently, dB, >= 0.

    Returns
    -------
    p_cum : ndarray, shape (T,)
        P(detected at one of looks 0..i), non-decreasing.
    """
    se = np.atleast_1d(np.asarray(excess_db, dtype=float))
    s = np.broadcast_to(np.asarray(persistent_db, dtype=float), se.shape)
    w = np.broadcast_to(np.asarray(per_look_db, dtype=float), se.shape)
    if np.any(s < 0) or np.any(w < 0):
        raise ValueError("cumulative_pd: the sds must be >= 0")
    usable = np.isfinite(se)
    # looks with no per-look part: the step SE + s z >= 0, i.e. z >= -SE / s (always or never when s = 0)
    step = usable & (w == 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        z_step = np.where(s > 0, -se / np.where(s > 0, s, 1.0), np.where(se >= 0, -np.inf, np.inf))
    z_star = np.minimum.accumulate(np.where(step, z_step, np.inf))    # undetected by the steps iff z < z*
    smooth = usable & (w > 0)
    width = np.where(smooth & (s > 0), w / np.where(s > 0, s, 1.0), np.inf)
    dz = min(Z_STEP, 0.25 * float(width.min())) if smooth.any() else Z_STEP
    nodes = min(Z_MAX_NODES, int(math.ceil(2 * Z_SPAN / dz)) + 1)
    z = np.linspace(-Z_SPAN, Z_SPAN, nodes)
    density = np.exp(-0.5 * z * z) / math.sqrt(2.0 * math.pi)
    log_miss = np.zeros(nodes)
    out = np.empty(se.shape)
    seen_smooth = False
    for i in range(se.size):
        if smooth[i]:
            seen_smooth = True
            miss = normal_cdf(-(se[i] + s[i] * z) / w[i])
            with np.errstate(divide="ignore"):
                log_miss += np.log(miss)
        if not seen_smooth:  # the steps alone: undetected iff z < z*, probability Phi(z*) exactly
            out[i] = float(normal_cdf(-z_star[i])) if np.isfinite(z_star[i]) else float(z_star[i] < 0)
        else:
            out[i] = 1.0 - _integral_below(z, density * np.exp(log_miss), z_star[i])
    return np.maximum.accumulate(np.clip(out, 0.0, 1.0))


def _integral_below(z: np.ndarray, f: np.ndarray, upper: float) -> float:
    """The trapezoid integral of f over z up to ``upper`` (beyond the nodes: all or nothing)."""
    if upper <= z[0]:
        return 0.0
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(z))])
    if upper >= z[-1]:
        return float(cum[-1])
    return float(np.interp(upper, z, cum))


#: The tail of the range axis whose K the extrapolation fits: this share of the axis, at least
#: `TAIL_MIN_POINTS` ranges.
TAIL_FRACTION = 0.25
TAIL_MIN_POINTS = 5
#: The spreading exponents the fit may take, 10 n lg r: cylindrical (n = 1) to spherical (n = 2).
SPREADING_DB_PER_DECADE = (10.0, 20.0)
#: Farthest an extrapolated range is sought, m.
REACH_LIMIT_M = 2.0e7


def tail_fit(range_m, k_db, beta_db_per_km) -> tuple[np.ndarray, np.ndarray]:
    """K's tail as `tail_reach_m` fits it: K(r) = A - m lg r - beta r beyond the table.

    Returns (A, m), each of shape ``k_db.shape[:-1]``: A in dB, m in dB per decade of range
    (clipped to `SPREADING_DB_PER_DECADE`); ``beta_db_per_km`` broadcasts with ``k_db[..., 0]``.
    """
    r = np.asarray(range_m, dtype=float)
    k = np.asarray(k_db, dtype=float)
    n_tail = max(TAIL_MIN_POINTS, int(math.ceil(TAIL_FRACTION * r.size)))
    rt = r[-n_tail:]
    beta = np.asarray(beta_db_per_km, dtype=float)[..., None] / 1000.0     # dB/m
    y = k[..., -n_tail:] + beta * rt
    x = np.log10(rt)
    xm = x.mean()
    slope = np.sum((x - xm) * (y - y.mean(axis=-1, keepdims=True)), axis=-1) / np.sum((x - xm) ** 2)
    m = np.clip(-slope, *SPREADING_DB_PER_DECADE)
    return np.mean(y + m[..., None] * x, axis=-1), m


def tail_k_db(a, m, beta_db_per_km, range_m) -> np.ndarray:
    """K of a fitted tail (`tail_fit`) at ranges, (..., R) for a and m of shape (...), dB."""
    r = np.asarray(range_m, dtype=float)
    beta = np.asarray(beta_db_per_km, dtype=float)[..., None] / 1000.0
    return np.asarray(a)[..., None] - np.asarray(m)[..., None] * np.log10(r) - beta * r


def tail_reach_m(range_m, k_db, beta_db_per_km, k_target_db) -> tuple[np.ndarray, np.ndarray]:
    """Where K(r) would fall to ``k_target_db`` beyond the table: K's tail extrapolated.

    Over the last `TAIL_FRACTION` of the range axis, K(r) + beta r (absorption added back) is
    fitted by least squares as A - m lg r, m the spreading loss per decade clipped to
    `SPREADING_DB_PER_DECADE` (a convergence-zone or modal tail can fit any slope); beyond the
    table K(r) = A - m lg r - beta r (`tail_fit`), solved for K = ``k_target_db`` by bisection.
    Where the fitted tail is already below the target at the table's end, the table's last range.

    Parameters
    ----------
    range_m : array_like, shape (R,)
        The table's ranges, m, increasing.
    k_db : array_like, shape (..., R)
        K(r), dB; a row with a NaN in its tail (beyond land) gives NaN.
    beta_db_per_km : array_like, broadcast with ``k_db[..., 0]``
        Volume attenuation at the band centre, dB/km.
    k_target_db : array_like, broadcast with ``k_db[..., 0]``
        The K sought (for P_D = p: K_needed + sigma Phi^-1(p)), dB.

    Returns
    -------
    reach_m, spreading_db_per_decade : ndarray, shape ``k_db.shape[:-1]``
    """
    r_end = float(np.asarray(range_m, dtype=float)[-1])
    a, m = tail_fit(range_m, k_db, beta_db_per_km)
    beta = np.broadcast_to(np.asarray(beta_db_per_km, dtype=float), a.shape) / 1000.0
    target = np.broadcast_to(np.asarray(k_target_db, dtype=float), a.shape)

    def k_fit(rr):
        return a - m * np.log10(rr) - beta * rr

    lo = np.full(a.shape, r_end)
    hi = np.full(a.shape, REACH_LIMIT_M)
    for _ in range(80):  # bisection in lg r: K_fit falls monotonically
        mid = np.sqrt(lo * hi)
        above = k_fit(mid) > target
        lo = np.where(above, mid, lo)
        hi = np.where(above, hi, mid)
    reach = np.where(k_fit(r_end) > target, np.sqrt(lo * hi), r_end)
    bad = ~np.isfinite(a)
    return np.where(bad, np.nan, reach), np.where(bad, np.nan, m)


def first_detection_times(t_s, p_cum) -> dict:
    """When the first detection comes, from the cumulative P_D at each look's time.

    Returns
    -------
    dict
        ``p_detected_by_end`` (P_cum at the last look); ``mean_s_given_detected``, the expected
        time of the first detection given one comes by the last look, s (None when P_cum stays
        0): sum of t_i (P_cum(t_i) - P_cum(t_{i-1})) / P_cum(end), P_cum(t_{-1}) = 0; and
        ``median_s``, ``p90_s``: the first look by which P_cum reaches 0.5 and 0.9, s (None where
        it does not by the last look). A track on which detection may never come has no
        unconditional mean: what it has is P_cum at its end.
    """
    t = np.asarray(t_s, dtype=float)
    p = np.asarray(p_cum, dtype=float)
    end = float(p[-1]) if p.size else 0.0
    gain = np.diff(np.concatenate([[0.0], p]))
    mean = float(np.sum(t * gain) / end) if end > 0 else None

    def first(level: float):
        hit = np.flatnonzero(p >= level)
        return float(t[hit[0]]) if hit.size else None

    return {"p_detected_by_end": end, "mean_s_given_detected": mean, "median_s": first(0.5),
            "p90_s": first(0.9)}


__all__ = ["PD_LEVELS", "any_band", "cumulative_pd", "first_detection_times", "normal_cdf",
           "normal_quantile", "pd_of_excess", "tail_fit", "tail_k_db",
           "tail_reach_m"]
