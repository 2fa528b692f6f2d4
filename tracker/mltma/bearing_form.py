"""The bearing term of eq. 25 in pseudo-linear form: a quadratic form in the target's motion
that is a running sum over the tack.

The bearing term sum_i (p_i - P(t_i, k, v, r))^2 / sigma_Pi^2 is evaluated as
sum_i w_i (u_i^perp . d_i)^2, with d_i the target's position relative to the observer at t_i,
u_i^perp = (cos p_i, -sin p_i) the unit normal of the measured bearing line and
w_i = 1 / (sigma_Pi^2 rho_i^2) (rho_i the range estimate when bearing i arrived; sigma_Pi in
radians). u^perp . d = rho sin(residual), so the two agree to first order and both vanish on
noiseless data.

With z = (x0, y0, vx, vy, 1), the target's position at the tack start (m) and its velocity
(m/s), u_i^perp . d_i = a_i . z with

    a_i = (cos p_i, -sin p_i, tau_i cos p_i, -tau_i sin p_i, -(ox_i cos p_i - oy_i sin p_i)),

tau_i = t_i - t_start and (ox_i, oy_i) the observer. The bearing term is z^T F z with the
5 x 5 matrix F = sum_i w_i a_i a_i^T, added to once per cycle: nothing is recomputed over old
bearings.

For a candidate with velocity v = (vx, vy) at range r along the current bearing p_N from the
observer (ox_N, oy_N), tau_N after the tack start, z = g + H v + r e_u with
g = (ox_N, oy_N, 0, 0, 1), H v = (-tau_N vx, -tau_N vy, vx, vy, 0) and
e_u = (sin p_N, cos p_N, 0, 0, 0), so z^T F z is quadratic in r:

    z^T F z = e r^2 + 2 r (f0 + f1 . v) + (c0 + 2 c1 . v + v^T C2 v).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


def cycle_term(bearing_deg, bearing_sd_deg, range_m, tau_s, obs_x_m: float, obs_y_m: float):
    """One cycle's w a a^T for each row, shape (b, 5, 5).

    Parameters
    ----------
    bearing_deg, bearing_sd_deg : ndarray, shape (b,)
        Bearing p_i and its sd sigma_Pi, deg.
    range_m : ndarray, shape (b,)
        rho_i, the range that weights the bearing, m.
    tau_s : ndarray, shape (b,)
        t_i minus the time of each row's tack start, s.
    obs_x_m, obs_y_m : float
        Observer position at t_i, m.
    """
    a = np.radians(bearing_deg)
    c, s = np.cos(a), np.sin(a)
    vec = np.stack([c, -s, c * tau_s, -s * tau_s, -(c * obs_x_m - s * obs_y_m)], axis=1)
    w = 1.0 / (np.square(np.radians(bearing_sd_deg)) * np.square(range_m))
    return w[:, None, None] * vec[:, :, None] * vec[:, None, :]


class RangeQuadratic(NamedTuple):
    """z^T F z = e r^2 + 2 r (f0 + f1 . v) + (c0 + 2 c1 . v + v^T C2 v), per row."""

    e: np.ndarray    # (b,)
    f0: np.ndarray   # (b,)
    f1: np.ndarray   # (b, 2)
    c0: np.ndarray   # (b,)
    c1: np.ndarray   # (b, 2)
    c2: np.ndarray   # (b, 2, 2)


def range_quadratic(form, tau_s, obs_x_m: float, obs_y_m: float, bearing_deg) -> RangeQuadratic:
    """The form F as a quadratic in range and velocity at the current cycle.

    Parameters
    ----------
    form : ndarray, shape (b, 5, 5)
        F of each row.
    tau_s : ndarray, shape (b,)
        Time since each row's tack start, s.
    obs_x_m, obs_y_m : float
        Observer position now, m.
    bearing_deg : ndarray, shape (b,)
        Current bearing, deg: the candidate lies at range r along it.
    """
    b = len(form)
    g = np.zeros((b, 5))
    g[:, 0], g[:, 1], g[:, 4] = obs_x_m, obs_y_m, 1.0
    H = np.zeros((b, 5, 2))
    H[:, 0, 0] = H[:, 1, 1] = -tau_s
    H[:, 2, 0] = H[:, 3, 1] = 1.0
    ze = np.zeros((b, 5))
    ze[:, 0], ze[:, 1] = np.sin(np.radians(bearing_deg)), np.cos(np.radians(bearing_deg))
    Ag = np.einsum("bij,bj->bi", form, g)
    AH = np.einsum("bij,bjk->bik", form, H)
    Aze = np.einsum("bij,bj->bi", form, ze)
    return RangeQuadratic(e=np.einsum("bi,bi->b", ze, Aze),
                          f0=np.einsum("bi,bi->b", ze, Ag), f1=np.einsum("bi,bik->bk", ze, AH),
                          c0=np.einsum("bi,bi->b", g, Ag), c1=np.einsum("bi,bik->bk", g, AH),
                          c2=np.einsum("bik,bil->bkl", H, AH))


def velocity_terms(q: RangeQuadratic, course_deg, speed_mps):
    """lin = f0 + f1 . v and const = c0 + 2 c1 . v + v^T C2 v at candidate velocities.

    Parameters
    ----------
    q : RangeQuadratic
    course_deg, speed_mps : ndarray, shape (b,) or (b, c)
        Candidates (c per row).

    Returns
    -------
    lin, const : ndarray, the candidates' shape
    """
    vx = speed_mps * np.sin(np.radians(course_deg))
    vy = speed_mps * np.cos(np.radians(course_deg))
    per_row = (slice(None),) + (None,) * (np.ndim(course_deg) - 1)   # broadcast over candidates
    f0, c0 = q.f0[per_row], q.c0[per_row]
    f1x, f1y = q.f1[:, 0][per_row], q.f1[:, 1][per_row]
    c1x, c1y = q.c1[:, 0][per_row], q.c1[:, 1][per_row]
    cxx, cxy, cyy = q.c2[:, 0, 0][per_row], q.c2[:, 0, 1][per_row], q.c2[:, 1, 1][per_row]
    lin = f0 + f1x * vx + f1y * vy
    const = (c0 + 2.0 * (c1x * vx + c1y * vy) + cxx * vx * vx + 2.0 * cxy * vx * vy
             + cyy * vy * vy)
    return lin, const
