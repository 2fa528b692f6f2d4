"""Course from bearings: the relative course by least squares over bearing triples (eq. 8,
Annex 1) and the course from a relative course and a speed (eq. 7).

Angles are degrees clockwise from north (docs/formats.md "Conventions"); differences are wrapped into [-180, 180).
"""

from __future__ import annotations

import numpy as np


def wrap180(a):
    """Angle or angle difference ``a`` (deg) wrapped into [-180, 180), as a float array."""
    return np.mod(np.asarray(a, dtype=float) + 180.0, 360.0) - 180.0


def relative_course_deg(t_s, bearing_deg, i0, i1, i2, valid):
    """Relative course by least squares over bearing triples (eq. 8 / A1.4, Annex 1).

    Each triple (P0, P1, P2) at (t0, t1, t2) gives the linear equation of A1.3 in
    (sin K_rho, cos K_rho); the unit vector minimising the sum of squares over the triples
    is the smallest eigenvector of a 2 x 2 matrix. The 180-deg ambiguity is resolved by the
    sense of the bearing change (the relative motion turns the bearing the same way).

    Parameters
    ----------
    t_s : ndarray, shape (T,)
        Cycle times, s.
    bearing_deg : ndarray, shape (B, T)
        Bearings of each row, deg.
    i0, i1, i2 : ndarray of int, shape (B, J)
        Cycle indices of the first, middle and last bearing of each of J triples.
    valid : ndarray of bool, shape (B, J)
        Triples that enter the least squares.

    Returns
    -------
    rel_course_deg : ndarray, shape (B,)
        K_rho in [0, 360), deg.
    """
    b = np.radians(bearing_deg)
    take = lambda idx: np.take_along_axis(b, idx, axis=1)  # noqa: E731
    p0, p1, p2 = take(i0), take(i1), take(i2)
    t0, t1, t2 = t_s[i0], t_s[i1], t_s[i2]
    # eq. 8 with P_1, P_k, P_N = p0, p1, p2 (A1.4 of the extraction has garbled indices; eq. 8
    # is the form that holds on noiseless data, see the tests)
    s10 = np.sin(p1 - p0) * (t2 - t1)
    s20 = np.sin(p2 - p1) * (t1 - t0)
    den = s10 * np.cos(p2) - s20 * np.cos(p0)      # coefficient of tan K_rho
    num = s10 * np.sin(p2) - s20 * np.sin(p0)
    # den sinK - num cosK = 0 ; scale each triple to unit norm (equal weight per triple)
    norm = np.hypot(den, num)
    ok = valid & (norm > 0)
    den = np.where(ok, den / np.where(ok, norm, 1.0), 0.0)
    num = np.where(ok, num / np.where(ok, norm, 1.0), 0.0)
    alpha = (den * den).sum(1)
    beta = (den * num).sum(1)
    gamma = (num * num).sum(1)
    # theta minimises alpha s^2 - 2 beta s c + gamma c^2
    theta = 0.5 * np.arctan2(2.0 * beta, alpha - gamma)
    k = np.degrees(theta)
    # sense: bearing increasing (clockwise) <=> sin(K_rho - P_last) > 0
    last = np.take_along_axis(bearing_deg, i2[:, -1:], axis=1)[:, 0]
    first = np.take_along_axis(bearing_deg, i0[:, :1], axis=1)[:, 0]
    change = wrap180(last - first)
    flip = np.sign(np.sin(np.radians(k - last))) != np.sign(change)
    return np.mod(k + np.where(flip, 180.0, 0.0), 360.0)


def bearing_triples(tack_start, n, triples: int):
    """Cycle indices of the eq.-8 bearing triples on each row's tack (cycles tack_start..n).

    Triple j takes its first bearing j steps into the tack's first quarter, its last j steps
    back from cycle n, and the middle one halfway between them (eq. 8 wants P_k near the
    mean of P_1 and P_N).

    Parameters
    ----------
    tack_start : ndarray of int, shape (B,)
        First cycle of each row's tack.
    n : int
        Current cycle.
    triples : int
        J, the number of triples.

    Returns
    -------
    i0, i1, i2 : ndarray of int, shape (B, J)
    valid : ndarray of bool, shape (B, J)
        Triples whose three cycles are distinct.
    """
    length = n - tack_start + 1
    j = np.arange(triples)[None, :]
    span = np.maximum(length // 4, 1)[:, None]
    i0 = tack_start[:, None] + (j * span) // triples
    i2 = n - (j * span) // triples
    i1 = (i0 + i2) // 2
    valid = (i0 < i1) & (i1 < i2)
    i0, i1, i2 = (np.clip(v, 0, n) for v in (i0, i1, i2))
    return i0, i1, i2, valid


def relative_course_on_tack_deg(t_s, bearing_deg, tack_start, n, triples: int):
    """Relative course (eq. 8) from the bearings of each row's tack up to cycle n, deg.

    ``t_s`` (T,) and ``bearing_deg`` (B, T) hold every cycle so far; see `bearing_triples`
    and `relative_course_deg`.
    """
    i0, i1, i2, valid = bearing_triples(tack_start, n, triples)
    return relative_course_deg(t_s[:n + 1], bearing_deg[:, :n + 1], i0, i1, i2, valid)


def course_from_relative_deg(k_rel_deg, v_mps, obs_course_deg, obs_speed_mps):
    """Course from relative course (eq. 7): K = K_rho - arcsin(V_n / V sin(K_rho - K_n)).

    Parameters
    ----------
    k_rel_deg : array_like
        Relative course K_rho, deg.
    v_mps : array_like
        Target speed V, m/s (floored at 1e-6).
    obs_course_deg, obs_speed_mps : float
        Observer's course K_n, deg, and speed V_n, m/s.

    Returns
    -------
    course_deg : ndarray
        K in [0, 360), deg; the arcsine's argument is clipped to [-1, 1].
    """
    arg = np.clip(obs_speed_mps / np.maximum(v_mps, 1e-6)
                  * np.sin(np.radians(k_rel_deg - obs_course_deg)), -1.0, 1.0)
    return np.mod(k_rel_deg - np.degrees(np.arcsin(arg)), 360.0)


def course_speed_slope_deg_per_mps(k_rel_deg, v_mps, obs_course_deg, obs_speed_mps):
    """|dK/dV| of eq. 7 at speed ``v_mps`` by a central difference (h = 0.05 m/s), deg per m/s.

    With the speed sd it widens the course sd of the fallback estimate (no eq. 25).
    """
    h = 0.05
    k1 = course_from_relative_deg(k_rel_deg, v_mps + h, obs_course_deg, obs_speed_mps)
    k0 = course_from_relative_deg(k_rel_deg, np.maximum(v_mps - h, 1e-3), obs_course_deg,
                                  obs_speed_mps)
    return np.abs(wrap180(k1 - k0)) / (2 * h)
