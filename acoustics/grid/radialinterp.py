"""A bearing-dependent grid between its radials: linear in bearing, across 0/360 deg.

README "Real areas": the trackers and the simulator take K
interpolated between radials. It is the one rule for the figures and the trackers
(``acoustics.grid.tables`` imports it): the two
radials around a bearing (clockwise), weighted linearly by the angle from each; a radial of
weight 0 does not count, even where it holds NaN, so a bearing on a radial gives that radial's
values exactly. A TL section takes the nearest radial instead (``nearest_radial``): TL over two
different bottoms does not mix.
"""

from __future__ import annotations

import numpy as np


def bearing_weights(bearings_deg: np.ndarray, bearing_deg) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The two radials around each bearing and the weight of the second.

    Parameters
    ----------
    bearings_deg : ndarray, shape (N,)
        The grid's radials, deg, increasing in [0, 360).
    bearing_deg : array_like
        Bearings to interpolate at, deg (taken modulo 360).

    Returns
    -------
    j0, j1 : ndarray of int
        Indices of the radials before and after each bearing (clockwise).
    w1 : ndarray
        Weight of radial ``j1``; ``1 - w1`` that of ``j0``.
    """
    grid = np.asarray(bearings_deg, dtype=float)
    b = np.mod(np.asarray(bearing_deg, dtype=float), 360.0)
    n = grid.size
    if n == 1:
        zero = np.zeros(b.shape, dtype=int)
        return zero, zero, np.zeros(b.shape)
    j1 = np.searchsorted(grid, b, side="right") % n
    j0 = (j1 - 1) % n
    span = np.mod(grid[j1] - grid[j0], 360.0)
    span = np.where(span == 0.0, 360.0, span)
    w1 = np.mod(b - grid[j0], 360.0) / span
    return j0, j1, w1


def at_bearings(values, bearings_deg: np.ndarray, bearing_deg) -> np.ndarray:
    """Values on the radials (bearing the first axis) at other bearings, linear between radials.

    Parameters
    ----------
    values : array_like, shape (N, ...)
        One entry per radial of ``bearings_deg``.
    bearings_deg : ndarray, shape (N,)
        The grid's radials, deg, increasing in [0, 360).
    bearing_deg : array_like, shape (B,) or scalar
        Bearings wanted, deg.

    Returns
    -------
    ndarray, shape (B, ...) (or ``values.shape[1:]`` for a scalar bearing)
        NaN where a radial of non-zero weight holds NaN.
    """
    v = np.asarray(values, dtype=float)
    j0, j1, w1 = bearing_weights(bearings_deg, bearing_deg)
    return mix(v[j0], v[j1], np.reshape(w1, np.shape(w1) + (1,) * (v.ndim - 1)))


def mix(a0, a1, w1):
    """(1 - w1) a0 + w1 a1, where a value of weight 0 does not count (even a NaN)."""
    return np.where(w1 <= 0.0, a0, np.where(w1 >= 1.0, a1, (1.0 - w1) * a0 + w1 * a1))


def nearest_radial(bearings_deg: np.ndarray, bearing_deg: float) -> int:
    """Index of the radial nearest to a bearing, across 0/360 (halfway: the one before it,
    counter-clockwise)."""
    j0, j1, w1 = bearing_weights(bearings_deg, bearing_deg)
    return int(j1) if float(w1) > 0.5 else int(j0)
