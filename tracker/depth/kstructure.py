"""K's structure along range, as a level likelihood may trust it: K averaged over a range
uncertainty and its spread there.

A table's K(r) ripples along range (interference between paths, caustics, the surface's
interference at a near-surface target's end). Where the track's range is uncertain by some
sigma_r, or where the table's ripple is not where the sea puts it (the tables are computed at
one position and depth step; the measurements are not), a likelihood that reads K at a point
treats every ripple as known: a filter locks onto a wrong one, and a depth whose ripple happens
to match a few cycles wins by more than the levels can say (docs/depth.md). Here K is read as
its mean over r' ~ N(r, sigma_r^2) and the level's variance gains K's variance there:

    K_s(r) = E[K(r')],   V_s(r) = Var[K(r')],   r' ~ N(r, sigma_r(r)^2),

sigma_r(r) = max(``floor_m``, ``fraction`` r): a range error that grows with range as the
trackers' do. On an axis the weights are a Gaussian kernel per output range (the scale changes
along the axis, so this is not a convolution); cells without a value (NaN: below the bottom,
beyond land) get no weight, and a range whose kernel holds none stays NaN.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Default range uncertainty over which K is averaged: this share of the range, m/m ...
K_SMOOTH_FRACTION = 0.05
#: ... and never less than this, m.
K_SMOOTH_FLOOR_M = 200.0
#: The kernel is cut at this many sd.
CUT_SD = 3.0


@dataclass(frozen=True, slots=True, kw_only=True)
class RangeSmoothing:
    """The range uncertainty over which K is averaged: sd = max(floor_m, fraction r).

    Attributes
    ----------
    fraction : float
        Share of the range, m/m (>= 0).
    floor_m : float
        Least sd, m (>= 0). Both 0: no smoothing.
    """

    fraction: float = K_SMOOTH_FRACTION
    floor_m: float = K_SMOOTH_FLOOR_M

    def __post_init__(self) -> None:
        for name in ("fraction", "floor_m"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v >= 0.0):
                raise ValueError(f"range smoothing {name} must be >= 0, got {v}")

    @property
    def off(self) -> bool:
        return self.fraction == 0.0 and self.floor_m == 0.0

    def sd_m(self, range_m) -> np.ndarray:
        """The range sd at ``range_m``, m."""
        return np.maximum(self.floor_m, self.fraction * np.asarray(range_m, dtype=float))


def kernel_weights(range_m, smoothing: RangeSmoothing) -> np.ndarray:
    """Weights (R, R): row j the Gaussian kernel of sd ``smoothing.sd_m(range_m[j])`` over the
    axis, each point weighted by the axis length it stands for (uneven axes), cut at
    ``CUT_SD``; not normalised (NaN cells drop out before)."""
    r = np.asarray(range_m, dtype=float)
    if r.size < 2 or smoothing.off:
        return np.eye(r.size)
    cell = np.gradient(r)
    sd = np.maximum(smoothing.sd_m(r), 1e-9)[:, None]
    u = (r[None, :] - r[:, None]) / sd
    w = np.where(np.abs(u) <= CUT_SD, np.exp(-0.5 * u * u), 0.0) * cell[None, :]
    return w


def smoothed_k(k_db, range_m, smoothing: RangeSmoothing) -> tuple[np.ndarray, np.ndarray]:
    """K averaged over the range uncertainty and its variance there, along the last axis.

    Parameters
    ----------
    k_db : array_like, shape (..., R)
        K on ``range_m``, dB; NaN where there is none.
    range_m : array_like, shape (R,)
        Increasing range axis, m.
    smoothing : RangeSmoothing

    Returns
    -------
    k_mean_db, k_var_db2 : ndarray, shape (..., R)
        K_s (NaN where the point itself has no K) and V_s, dB and dB^2 (0 without smoothing).
    """
    k = np.asarray(k_db, dtype=float)
    if smoothing.off:
        return k.copy(), np.where(np.isfinite(k), 0.0, np.nan)
    w = kernel_weights(range_m, smoothing)                      # (R_out, R_in)
    have = np.isfinite(k)
    k0 = np.where(have, k, 0.0)
    s0 = have.astype(float) @ w.T
    s1 = k0 @ w.T
    s2 = (k0 * k0) @ w.T
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = s1 / s0
        var = np.maximum(s2 / s0 - mean * mean, 0.0)
    mean = np.where(have, mean, np.nan)
    var = np.where(have, var, np.nan)
    return mean, var
