"""Cramér-Rao lower bound of bearings-only tracking with zero process noise.

Ristic, Arulampalam & Gordon (2003), sec. 4.3.3: for deterministic target motion
x_{k+1} = F x_k - u_k (relative state, the observer's motion u_k known), the information matrix
follows

    J_{k+1} = F^{-T} J_k F^{-1} + H_{k+1}^T R^{-1} H_{k+1},

with H the Jacobian of the bearing h = arctan(x / y) (eq. 9) at the true state,
H = [y / r^2, -x / r^2, 0, 0], R = sigma_theta^2, and J_0 = P_0^{-1} the inverse of the
initial covariance of the filter's prior (Ristic sec. 6.4.1.1; the first bearing is in it).
The bound on the position RMSE is sqrt([J^-1]_xx + [J^-1]_yy).

With sound pressure levels (`bot_spl_crlb`, not in the paper) each cycle adds the level's
information H_l^T H_l / sigma_l^2, with h_l = SL(|v_t|) + K(r) (eq. 16): Ross's source level of
the target's own speed v_t = v_rel + v_obs and the transfer characteristic at the range, so
H_l = [K'(r) x / r, K'(r) y / r, SL'(v) v_tx / v, SL'(v) v_ty / v], SL'(v) = 53 / (v ln 10).
K'(r) is the slope of the grid's K(r) (linear between range nodes). The bound is local: where
K(r) is flat the level adds nothing on range, where it steps it adds a lot.
"""

from __future__ import annotations

import math

import numpy as np


def prior_covariance(bearing_rad: float, *, range_mean_m: float, range_sd_m: float,
                     bearing_sd_rad: float, speed_mean_mps: float, speed_sd_mps: float,
                     course_sd_rad: float) -> np.ndarray:
    """P_0 of the filter's prior linearised at its means (Ristic et al. sec. 6.4.1.1).

    Range r ~ N(r_bar, sd_r) on bearing theta ~ N(z0, sd_theta) gives
    P_xx = r^2 sd_theta^2 cos^2 + sd_r^2 sin^2, P_yy = r^2 sd_theta^2 sin^2 + sd_r^2 cos^2,
    P_xy = (sd_r^2 - r^2 sd_theta^2) sin cos; the velocity block is the same with speed and the
    course z0 + pi.
    """
    def block(mag, mag_sd, ang, ang_sd):
        s, c = math.sin(ang), math.cos(ang)
        a = (mag * ang_sd) ** 2
        b = mag_sd ** 2
        return np.array([[a * c * c + b * s * s, (b - a) * s * c],
                         [(b - a) * s * c, a * s * s + b * c * c]])

    p = np.zeros((4, 4))
    p[:2, :2] = block(range_mean_m, range_sd_m, bearing_rad, bearing_sd_rad)
    p[2:, 2:] = block(speed_mean_mps, speed_sd_mps, bearing_rad + math.pi, course_sd_rad)
    return p


def bot_crlb(t_s, rel_state, *, bearing_sd_rad: float, p0: np.ndarray) -> np.ndarray:
    """Position CRLB of bearings-only tracking with zero process noise (Ristic sec. 4.3.3).

    Parameters
    ----------
    t_s : array_like, shape (K,)
        Measurement times, s.
    rel_state : array_like, shape (K, 4)
        True relative state (x, y, vx, vy) at those times, m and m/s.
    bearing_sd_rad : float
        sigma_theta, rad.
    p0 : ndarray, shape (4, 4)
        Covariance of the prior at the first time (which already holds the first bearing).

    Returns
    -------
    bound_m : ndarray, shape (K,)
        sqrt of the position part of J_k^{-1}, m.
    """
    return _crlb(t_s, rel_state, p0, lambda k, x: [_bearing_row(x) / bearing_sd_rad])


def bot_spl_crlb(t_s, rel_state, obs_vel_mps, *, bearing_sd_rad: float, level_sd_db: float,
                 k_profile, p0: np.ndarray) -> np.ndarray:
    """Position CRLB with bearings and sound pressure levels, zero process noise.

    Parameters
    ----------
    t_s, rel_state, bearing_sd_rad, p0
        As `bot_crlb`.
    obs_vel_mps : array_like, shape (K, 2)
        Observer velocity (east, north) at those times, m/s.
    level_sd_db : float
        sd of the measured level, dB (the data's, not the filter's sigma_l).
    k_profile : tracker.tables.LevelProfile
        K(r) at the observer depth, dB.

    Returns
    -------
    bound_m : ndarray, shape (K,)
        sqrt of the position part of J_k^{-1}, m.
    """
    vo = np.asarray(obs_vel_mps, dtype=float)
    r_axis = np.asarray(k_profile.range_m, dtype=float)
    half = 0.5 * float(np.min(np.diff(r_axis)))

    def rows(k, x):
        r = math.hypot(x[0], x[1])
        lo, hi = max(r - half, r_axis[0]), min(r + half, r_axis[-1])   # inside the grid
        slope = float(k_profile(hi) - k_profile(lo)) / (hi - lo) if hi > lo else 0.0
        vx, vy = x[2] + vo[k, 0], x[3] + vo[k, 1]
        v = max(math.hypot(vx, vy), 1e-3)
        dsl = 53.0 / (v * math.log(10.0))
        level = np.array([slope * x[0] / r, slope * x[1] / r, dsl * vx / v, dsl * vy / v])
        return [_bearing_row(x) / bearing_sd_rad, level / level_sd_db]

    return _crlb(t_s, rel_state, p0, rows)


def _bearing_row(x) -> np.ndarray:
    """Jacobian of the bearing arctan(x / y) by (x, y, vx, vy)."""
    r2 = x[0] ** 2 + x[1] ** 2
    return np.array([x[1] / r2, -x[0] / r2, 0.0, 0.0])


def _crlb(t_s, rel_state, p0, rows) -> np.ndarray:
    """The recursion J_{k+1} = F^-T J_k F^-1 + sum of h h^T over ``rows(k, x_k)`` (each row
    already divided by its measurement sd)."""
    t = np.asarray(t_s, dtype=float)
    x = np.asarray(rel_state, dtype=float)
    j = np.linalg.inv(p0)
    out = np.empty(t.size)
    out[0] = math.sqrt(max(np.trace(np.linalg.inv(j)[:2, :2]), 0.0))
    for k in range(1, t.size):
        dt = t[k] - t[k - 1]
        f_inv = np.array([[1.0, 0.0, -dt, 0.0], [0.0, 1.0, 0.0, -dt],
                          [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]])
        j = f_inv.T @ j @ f_inv
        for h in rows(k, x[k]):
            j += np.outer(h, h)
        cov = np.linalg.inv(j)
        out[k] = math.sqrt(max(cov[0, 0] + cov[1, 1], 0.0))
    return out
