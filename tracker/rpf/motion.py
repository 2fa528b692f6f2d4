"""Motion model of the filter: discrete white-noise acceleration, eqs. 4-6.

References
----------
E. Iglesis, L. de Montella (2024), eqs. 4-6.
"""

from __future__ import annotations

import numpy as np

from tracker.rpf.normals import standard_normal_pairs
from tracker.rpf.scratch import scratch


def predict(state: np.ndarray, *, dt_s: float, obs_k: np.ndarray, obs_k1: np.ndarray,
            sigma_a_mps2: float | np.ndarray, rng: np.random.Generator, work: dict | None = None) -> None:
    """Propagate the relative state one step in place, eq. 4: x' = F (x + x^o_k) - x^o_k1 + G nu.

    Parameters
    ----------
    state : ndarray, shape (D, ...)
        Relative state (x, y, vx, vy[, offset]) per particle, m and m/s; changed in place.
    dt_s : float
        Delta T, s.
    obs_k, obs_k1 : array_like, shape (4,)
        Observer state (x, y, vx, vy) at steps k and k+1, m and m/s.
    sigma_a_mps2 : float or ndarray, shape state.shape[1:]
        Acceleration sd, m/s^2 (nu ~ N(0, sigma_a^2 I), eq. 6 for Gamma): one, or each particle's.
    rng : numpy.random.Generator
        Source of nu (two float32 normals per particle, `standard_normal_pairs`).
    work : dict, optional
        Scratch arrays (`tracker.rpf.scratch`).
    """
    ox, oy, ovx, ovy = (float(v) for v in obs_k)
    nx, ny, nvx, nvy = (float(v) for v in obs_k1)
    # x_k1 = x + dt (v + dv / 2) + c, v_k1 = v + dv + c', with dv = dt nu: G nu of eq. 6 fused
    tmp = scratch(work, "tmp", state.shape[1:])
    for pos, vel, cp, cv in ((0, 2, ox + dt_s * ovx - nx, ovx - nvx),
                             (1, 3, oy + dt_s * ovy - ny, ovy - nvy)):
        if np.any(sigma_a_mps2 > 0):
            if pos == 0:
                nu = standard_normal_pairs(state.shape[1:], rng, work)
            dv = nu[pos]
            dv *= dt_s * sigma_a_mps2
            np.multiply(dv, 0.5, out=tmp)
            tmp += state[vel]
            state[vel] += dv
        else:
            tmp[...] = state[vel]
        tmp *= dt_s
        tmp += cp
        state[pos] += tmp
        state[vel] += cv
