"""Eq. 25, the joint ML estimate of course, speed and range: its inputs, its result, the speed
interval it is searched over, and its residuals as written (exact bearing residuals).

    J(k, v, r) = (r - R_opt)^2 / sigma_R^2 + (v - mV)^2 / sV^2 + (k - mK(v))^2 / sK_rho^2
                 + sum_i (p_i - P(t_i, k, v, r))^2 / sigma_Pi^2,

mK(v) the course of eq. 7 from the relative course at speed v, P(t_i, k, v, r) the bearing at
t_i of a target now at range r on the current bearing, moving with course k and speed v.
The fast search (`tracker.mltma.search`) minimises J with the bearing term in pseudo-linear
form; the polish (`tracker.mltma.polish`) minimises J as written, with these residuals.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from tracker.mltma.course import course_from_relative_deg, wrap180
from tracker.mltma.window import TackWindow


@dataclass(frozen=True, slots=True, kw_only=True)
class Eq25Terms:
    """Everything in eq. 25 but the bearings, for b rows."""

    range_m: np.ndarray             # (b,) R_opt: level range (eq. 20) or last range; NaN: none
    range_sd_m: np.ndarray          # (b,) its sd (eq. 21); inf or NaN: no range term
    speed_mean_mps: np.ndarray      # (b,) mV of the row's class
    speed_sd_mps: np.ndarray        # (b,) sV
    rel_course_deg: np.ndarray      # (b,) K_rho: eq. 8 or the reverse bearing
    rel_course_sd_deg: np.ndarray   # (b,) sK_rho
    obs_course_deg: float           # K_n of eq. 7
    obs_speed_mps: float            # V_n of eq. 7


class Eq25Estimate(NamedTuple):
    """Minimiser of eq. 25 and its sds from the curvature of J (J = -2 log L), per row."""

    course_deg: np.ndarray
    speed_mps: np.ndarray
    range_m: np.ndarray
    course_sd_deg: np.ndarray
    speed_sd_mps: np.ndarray
    range_sd_m: np.ndarray


def speed_interval_mps(terms: Eq25Terms, span_sd: float):
    """The speeds searched: mV +- ``span_sd`` sV, not below 0.2 m/s; (lo, hi), each (b,)."""
    lo = np.maximum(terms.speed_mean_mps - span_sd * terms.speed_sd_mps, 0.2)
    hi = terms.speed_mean_mps + span_sd * terms.speed_sd_mps
    return lo, hi


def residuals(window: TackWindow, terms: Eq25Terms, course_deg, speed_mps, range_m,
              jacobian: bool = False):
    """Residuals of eq. 25 as written, so that J = sum of their squares; (b, N + 3).

    The first N are the bearings' (p_i - P(t_i, k, v, r)) / sigma_Pi over the window (0 off
    each row's tack), then the range, speed and course terms.

    Parameters
    ----------
    window : TackWindow
        The rows' tacks up to the current cycle (the window's last column).
    terms : Eq25Terms
    course_deg, speed_mps, range_m : ndarray, shape (b,)
        The point (k, v, r).
    jacobian : bool
        Also return the derivatives by (course deg, speed m/s, range m), (b, N + 3, 3):
        analytic for the bearings, central differences for mK(v) of eq. 7.
    """
    k_deg, v, r = course_deg, speed_mps, range_m
    on = window.on_tack
    a = np.radians(window.bearing_deg[:, -1])
    dt = (window.t_s[-1] - window.t_s)[None, :]
    kr = np.radians(k_deg)
    sk, ck = np.sin(kr)[:, None], np.cos(kr)[:, None]
    dx = (window.obs_x_m[-1] + r * np.sin(a))[:, None] - v[:, None] * sk * dt \
        - window.obs_x_m[None, :]
    dy = (window.obs_y_m[-1] + r * np.cos(a))[:, None] - v[:, None] * ck * dt \
        - window.obs_y_m[None, :]
    pred = np.degrees(np.arctan2(dx, dy))
    inv_sd = np.where(on, 1.0 / window.bearing_sd_deg, 0.0)
    res_b = wrap180(window.bearing_deg - pred) * inv_sd
    mk = course_from_relative_deg(terms.rel_course_deg, v, terms.obs_course_deg,
                                  terms.obs_speed_mps)
    r0, r_sd = terms.range_m, terms.range_sd_m
    inv = np.where(np.isfinite(r_sd), 1.0 / r_sd, 0.0)
    res_p = np.stack([(r - np.where(np.isfinite(r0), r0, 0.0)) * inv,
                      (v - terms.speed_mean_mps) / terms.speed_sd_mps,
                      wrap180(k_deg - mk) / terms.rel_course_sd_deg], axis=1)
    f = np.concatenate([res_b, res_p], axis=1)
    if not jacobian:
        return f
    # d pred / d(dx, dy) = (dy, -dx) / rho^2 (radians); residual = -(180/pi) pred / sd
    rho2 = np.maximum(dx * dx + dy * dy, 1e-6)
    gx, gy = dy / rho2, -dx / rho2
    c = -np.degrees(1.0) * inv_sd
    vv = v[:, None]
    d_k = c * (gx * (-vv * ck * dt) + gy * (vv * sk * dt)) * (math.pi / 180.0)
    d_v = c * (gx * (-sk * dt) + gy * (-ck * dt))
    d_r = c * (gx * np.sin(a)[:, None] + gy * np.cos(a)[:, None])
    Jb = np.stack([d_k, d_v, d_r], axis=2)
    h = 1e-3
    dmk = wrap180(course_from_relative_deg(terms.rel_course_deg, v + h, terms.obs_course_deg,
                                           terms.obs_speed_mps)
                  - course_from_relative_deg(terms.rel_course_deg, np.maximum(v - h, 1e-6),
                                             terms.obs_course_deg, terms.obs_speed_mps)) / (2 * h)
    Jp = np.zeros((len(v), 3, 3))
    Jp[:, 0, 2] = inv
    Jp[:, 1, 1] = 1.0 / terms.speed_sd_mps
    Jp[:, 2, 0] = 1.0 / terms.rel_course_sd_deg
    Jp[:, 2, 1] = -dmk / terms.rel_course_sd_deg
    return f, np.concatenate([Jb, Jp], axis=1)
