"""Cramér-Rao lower bound of bearings-only tracking with zero process noise.

Ristic, Arulampalam & Gordon (2003), sec. 4.3.3: for deterministic target motion
x_{k+1} = F x_k - u_k (relative state, the observer's motion u_k known), the information matrix
follows

    J_{k+1} = F^{-T} J_k F^{-1} + H_{k+1}^T R^{-1} H_{k+1},

with H the Jacobian of the bearing h = arctan(x / y) (eq. 9) at the true state,
H = [y / r^2, -x / r^2, 0, 0], R = sigma_theta^2, and J_0 = P_0^{-1} the inverse of the
initial covariance of the filter's prior (Ristic sec. 6.4.1.1; the first bearing is in it).
The bound on the position RMSE is sqrt([J^-1]_xx + [J^-1]_yy).
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
    t = np.asarray(t_s, dtype=float)
    x = np.asarray(rel_state, dtype=float)
    j = np.linalg.inv(p0)
    out = np.empty(t.size)
    out[0] = math.sqrt(max(np.trace(np.linalg.inv(j)[:2, :2]), 0.0))
    for k in range(1, t.size):
        dt = t[k] - t[k - 1]
        f_inv = np.array([[1.0, 0.0, -dt, 0.0], [0.0, 1.0, 0.0, -dt],
                          [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]])
        r2 = x[k, 0] ** 2 + x[k, 1] ** 2
        h = np.array([x[k, 1] / r2, -x[k, 0] / r2, 0.0, 0.0])
        j = f_inv.T @ j @ f_inv + np.outer(h, h) / bearing_sd_rad ** 2
        cov = np.linalg.inv(j)
        out[k] = math.sqrt(max(cov[0, 0] + cov[1, 1], 0.0))
    return out
