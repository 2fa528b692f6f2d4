"""Bearing-line geometry and its conditioning (Schmidt et al., eqs. 1-12).

A stationary target at (x0, y0) seen from observer positions (X(n), Y(n)) at bearings alpha(n)
satisfies one linear equation per bearing (eq. 4),

    cos(alpha) x0 - sin(alpha) y0 = cos(alpha) X - sin(alpha) Y,

so that n bearings form the system P x = b (eqs. 5-7) and two of them cross at x = P^-1 b
(eq. 8). The conditioning number u of P (eq. 11) and its determinant (eq. 10) say how sensitive
a fix is to bearing errors.

Conventions (docs/formats.md): x east, y north, metres; bearings in degrees clockwise from north in
[0, 360).
"""

from __future__ import annotations

import math

import numpy as np

#: Observer positions that agree when rounded to this step count as the same position, m.
SAME_POSITION_M = 1e-3


def bearing_to_deg(from_x_m, from_y_m, to_x_m, to_y_m) -> np.ndarray:
    """Bearing from one point to another, degrees clockwise from north in [0, 360) (eqs. 1-3)."""
    deg = np.degrees(np.arctan2(np.subtract(to_x_m, from_x_m), np.subtract(to_y_m, from_y_m)))
    return np.mod(deg, 360.0) % 360.0  # the second mod maps a rounded 360.0 to 0.0


def wrap_deg(angle_deg) -> np.ndarray:
    """Angle wrapped to [-180, 180) deg."""
    return np.mod(np.asarray(angle_deg, dtype=float) + 180.0, 360.0) - 180.0


def bearing_system(obs_x_m, obs_y_m, bearing_deg) -> tuple[np.ndarray, np.ndarray]:
    """The linear system P x = b of eqs. 4-7, one row per bearing.

    Parameters
    ----------
    obs_x_m, obs_y_m : array_like
        Observer positions X(n), Y(n), m.
    bearing_deg : array_like
        Bearings alpha(n), deg.

    Returns
    -------
    p : ndarray, shape (n, 2)
        Rows (c_n, -s_n) with c_n = cos(alpha(n)), s_n = sin(alpha(n)) (eq. 5).
    b : ndarray, shape (n,)
        c_n X(n) - s_n Y(n), m (eq. 6).
    """
    a = np.radians(np.asarray(bearing_deg, dtype=float))
    c, s = np.cos(a), np.sin(a)
    p = np.column_stack([c, -s])
    b = c * np.asarray(obs_x_m, dtype=float) - s * np.asarray(obs_y_m, dtype=float)
    return p, b


def conditioning_number(bearing_deg) -> float:
    """Conditioning number u of P, the ratio of its largest to smallest singular value (eq. 11).

    Parameters
    ----------
    bearing_deg : array_like
        Two or more bearings, deg. P depends on the bearings only, not on the positions.

    Returns
    -------
    u : float
        s_max / s_min >= 1; ``inf`` for parallel bearing lines. For two bearings
        u = cot(|alpha1 - alpha2| / 2) when they differ by at most 90 deg, so that 30 and
        31 deg give u = 114.6 (the paper's example gives "about 115").
    """
    p, _ = bearing_system(np.zeros(np.size(bearing_deg)), np.zeros(np.size(bearing_deg)),
                          bearing_deg)
    sv = np.linalg.svd(p, compute_uv=False)
    return float(sv[0] / sv[-1]) if sv[-1] > 8.0 * np.finfo(float).eps * sv[0] else math.inf


def pair_conditioning(delta_deg) -> np.ndarray:
    """u (eq. 11) of two bearings differing by ``delta_deg``, vectorised.

    The rows of P are unit vectors at an angle delta, so its singular values are
    sqrt(1 +- |cos delta|) and u = sqrt((1 + |cos delta|) / (1 - |cos delta|)).
    """
    c = np.abs(np.cos(np.radians(np.asarray(delta_deg, dtype=float))))
    with np.errstate(divide="ignore"):
        return np.sqrt((1.0 + c) / np.maximum(1.0 - c, 0.0))


def crossing_point(x1_m, y1_m, a1_deg, x2_m, y2_m, a2_deg):
    """Crossing of two bearing lines (eqs. 6-8), vectorised over any broadcastable inputs.

    Returns
    -------
    x_m, y_m : ndarray
        The crossing, m (``inf``/``nan`` for parallel lines).
    r1_m, r2_m : ndarray
        Signed distance from each observer along its bearing to the crossing, m; negative
        when the lines cross behind that observer.
    determinant : ndarray
        |P| = sin(alpha1 - alpha2) (eq. 10).
    """
    a1, a2 = np.radians(a1_deg), np.radians(a2_deg)
    dx = np.subtract(x2_m, x1_m)
    dy = np.subtract(y2_m, y1_m)
    det = np.sin(a1 - a2)  # eq. 10
    with np.errstate(divide="ignore", invalid="ignore"):
        r1 = (np.cos(a2) * dx - np.sin(a2) * dy) / det  # law of sines in the bearing triangle
        r2 = (np.cos(a1) * dx - np.sin(a1) * dy) / det
        x = np.add(x1_m, r1 * np.sin(a1))
        y = np.add(y1_m, r1 * np.cos(a1))
    return x, y, r1, r2, det
