"""Measurement functions and log-likelihoods of bearings and levels, eqs. 9, 12, 16, 31-33.

The SPL of a particle is h_l = SL(v) - TL (eqs. 11-16): SL(v) = 170 + 53 lg(v / 5.14 m/s)
(eq. 12, Ross, `envdata.classes.ross_source_level_db`) with v the particle's own target speed,
TL read from the grid by linear interpolation in depth and range (eq. 13, `acoustics.grid.face`).

References
----------
E. Iglesis, L. de Montella (2024), eqs. 9, 12, 16, 31-33.
"""

from __future__ import annotations

import math

import numpy as np

from envdata.classes import SourceLevelModel, ross_source_level_db
from tracker.rpf.scratch import scratch


def bearing_rad(x_m, y_m):
    """h_theta of eq. 9: bearing clockwise from north (the y axis), rad, in (-pi, pi]."""
    return np.arctan2(x_m, y_m)


def wrap_rad(angle):
    """Angle wrapped to [-pi, pi)."""
    return np.mod(np.asarray(angle) + math.pi, 2.0 * math.pi) - math.pi


def bearing_loglik(state: np.ndarray, bearing_meas_rad, sigma_rad,
                   work: dict | None = None) -> np.ndarray:
    """Log of eq. 32 up to a constant: -(theta - h_theta(x))^2 / (2 sigma^2), angle wrapped.

    Parameters
    ----------
    state : ndarray, shape (D, ...)
        Relative state per particle, m and m/s.
    bearing_meas_rad : array_like
        Measured bearing theta, rad; broadcasts against the particle axes (e.g. shape
        (runs, 1)).
    sigma_rad : float or array_like
        sigma_theta, rad; broadcasts against the particle axes like the bearing.
    work : dict, optional
        Scratch arrays (`tracker.rpf.scratch`); the result lives in one of them.

    Returns
    -------
    loglik : ndarray, shape of the particle axes
    """
    # rotate each particle by -theta: atan2 of the rotated position is h_theta - theta, wrapped
    z = np.asarray(bearing_meas_rad, dtype=float)
    c, s = np.cos(z), np.sin(z)
    shape = np.broadcast_shapes(state.shape[1:], z.shape)
    east, north, tmp = (scratch(work, name, shape) for name in ("east", "north", "tmp"))
    np.multiply(state[0], c, out=east)
    east -= np.multiply(state[1], s, out=tmp)
    np.multiply(state[1], c, out=north)
    north += np.multiply(state[0], s, out=tmp)
    resid = np.arctan2(east, north, out=east)
    resid *= resid
    resid *= -0.5 / (sigma_rad * sigma_rad)
    return resid


def predicted_level_db(state: np.ndarray, obs_vel_mps, k_profile, *,
                       source_level_model: SourceLevelModel | str = SourceLevelModel.ROSS,
                       p0_db: float = math.nan) -> np.ndarray:
    """h_l of eq. 16: SL of each particle's target speed plus K(r) = S - TL(r), dB.

    Parameters
    ----------
    state : ndarray, shape (D, ...)
        Relative state; the target's own velocity is the relative velocity plus the
        observer's. A fifth component, if present, is a source-level offset, dB.
    obs_vel_mps : array_like, shape (2,)
        Observer velocity (east, north), m/s.
    k_profile : callable
        K(r) at the observer depth, dB (`tracker.tables.LevelProfile`).
    source_level_model : SourceLevelModel
        ``ROSS`` (eq. 12, the particle's speed) or ``P0`` (the constant ``p0_db``).
    p0_db : float
        Source level of the ``P0`` model, dB.

    Returns
    -------
    level_db : ndarray, shape of the particle axes
    """
    r = np.hypot(state[0], state[1])
    if SourceLevelModel(source_level_model) is SourceLevelModel.ROSS:
        v = np.hypot(state[2] + float(obs_vel_mps[0]), state[3] + float(obs_vel_mps[1]))
        level = ross_source_level_db(v)
    else:
        level = np.full(r.shape, p0_db)
    level += k_profile(r)
    if state.shape[0] > 4:
        level += state[4]
    return level


def level_loglik(state: np.ndarray, level_meas_db, obs_vel_mps, k_profile, sigma_db: float, *,
                 source_level_model: SourceLevelModel | str = SourceLevelModel.ROSS,
                 p0_db: float = math.nan) -> np.ndarray:
    """Log of eq. 33 up to a constant: -(l - h_l(x))^2 / (2 sigma_l^2).

    Parameters as `predicted_level_db`; ``level_meas_db`` is l, dB re 1 uPa, broadcasting
    against the particle axes, and ``sigma_db`` is sigma_l, dB. A profile carrying the grid's K
    error sd (``k_sd_db``) adds it at each particle's range: variance sigma_l^2 + sd(r)^2 in the
    quadratic term. The normal density's -1/2 ln(variance) is left out: the K error is not drawn
    anew each cycle but persists along the track (a member's K is wrong the same way from one
    cycle to the next), so that term, applied every cycle, would add up to a pull of the
    particles towards ranges where K is well known whatever the levels say (measured on the
    48 runs of docs/sensitivity.md's shelf study: a mean position RMSE after 5 min of 8.6 km
    with it, 2.3 km without).
    """
    pred = predicted_level_db(state, obs_vel_mps, k_profile, source_level_model=source_level_model,
                              p0_db=p0_db)
    if getattr(k_profile, "k_sd_db", None) is None:
        return -0.5 * ((level_meas_db - pred) / sigma_db) ** 2
    # the grid's K error sd at each particle's range adds to sigma_l (as the compiled kernel)
    var = sigma_db ** 2 + k_profile.sd_at(np.hypot(state[0], state[1])) ** 2
    return -0.5 * (level_meas_db - pred) ** 2 / var
