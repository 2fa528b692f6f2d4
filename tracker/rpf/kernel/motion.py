"""Prediction in the compiled kernel: eq. 4 per particle and over a run's particle arrays.

Discrete white-noise acceleration (eqs. 4-6), as `tracker.rpf.motion.predict`, with the
process noise drawn beforehand (`tracker.rpf.kernel.random.fill_normal_pairs`).
"""

from __future__ import annotations

from numba import njit


@njit(inline="always")
def predict_axis(pos, vel, g, dt_s, dv_scale, cp, cv):
    """Eq. 4 along one axis for one particle: x' = F (x + x^o_k) - x^o_k1 + G nu with
    nu = sigma_a g; ``dv_scale`` = dt sigma_a, ``cp`` = x^o_k + dt v^o_k - x^o_k1 and
    ``cv`` = v^o_k - v^o_k1 (observer position and velocity terms)."""
    dv = g * dv_scale
    return pos + ((vel + 0.5 * dv) * dt_s + cp), (vel + dv) + cv


@njit(inline="always")
def predict_pass(pos, vel, g, dt, dv_scale, cp, cv):
    """Eq. 4 along one axis over 1-D particle arrays, ``dv_scale`` each particle's dt sigma_a (its
    own acceleration sd, `tracker.rpf.config.RpfConfig.sigma_a_mix_mps2`); one loop, two arrays
    written: few alias checks, so it vectorizes."""
    for i in range(pos.size):
        pos[i], vel[i] = predict_axis(pos[i], vel[i], g[i], dt, dv_scale[i], cp, cv)
