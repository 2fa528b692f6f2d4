"""Compiled helpers the kernel tests call from Python: each runs a piece of
`tracker.rpf.kernel` over arrays the way the fused loop does, or draws many numbers from a
generator state. Test code only; the library has no use for them."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from tracker.rpf.kernel.estimate import particle_sds_run
from tracker.rpf.kernel.fastmath import FASTMATH
from tracker.rpf.kernel.likelihood import bearing_pass, k_at, level_loglik_particle, level_loglik_particle_sd
from tracker.rpf.kernel.motion import predict_pass
from tracker.rpf.kernel.prior import init_particle
from tracker.rpf.kernel.random import exponential, fill_exponentials, fill_normal_pairs, normal_pair, uniform
from tracker.rpf.kernel.regularise import fill_epanechnikov
from tracker.rpf.kernel.resample import resample_indices


@njit(cache=True, error_model="numpy")
def uniforms(s, n):
    """``n`` uniforms from the state ``s`` (for tests)."""
    out = np.empty(n)
    for i in range(n):
        out[i] = uniform(s)
    return out


@njit(cache=True, error_model="numpy")
def normals(s, n):
    """``2 n`` normals from the state ``s`` (for tests)."""
    out = np.empty(2 * n)
    for i in range(n):
        out[2 * i], out[2 * i + 1] = normal_pair(s)
    return out


@njit(cache=True, error_model="numpy")
def normal_pairs_filled(s, n):
    """`fill_normal_pairs` into two new arrays of ``n`` (for tests)."""
    gx = np.empty(n)
    gy = np.empty(n)
    fill_normal_pairs(s, gx, gy)
    return gx, gy


@njit(cache=True, error_model="numpy")
def exponentials(s, n):
    """``n`` standard exponentials from the state ``s`` (for tests)."""
    out = np.empty(n)
    for i in range(n):
        out[i] = exponential(s)
    return out


@njit(cache=True, error_model="numpy")
def exponentials_filled(s, n):
    """`fill_exponentials` into a new array of ``n`` (for tests)."""
    out = np.empty(n)
    fill_exponentials(s, out)
    return out


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def predict_arrays(state, gx, gy, dt, dv_scale, cpx, cpy, cvx, cvy):
    """Eq. 4 for (D, N) particles with noise (gx, gy), every particle's dt sigma_a ``dv_scale``
    (as the fused loop; for tests)."""
    scale = np.full(state.shape[1], dv_scale)
    predict_pass(state[0], state[2], gx, dt, scale, cpx, cvx)
    predict_pass(state[1], state[3], gy, dt, scale, cpy, cvy)


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def bearing_loglik_arrays(state, z, sigma_rad):
    """Eq. 32 for (D, N) particles (as the fused loop; for tests)."""
    out = np.zeros(state.shape[1])
    bearing_pass(state[0], state[1], out, math.cos(z), math.sin(z),
                  0.5 / (sigma_rad * sigma_rad))
    return out


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def level_loglik_arrays(state, level_db, ovx, ovy, ross, p0_db, xp, fp, sigma_db):
    """Eq. 33 for (D, N) particles (as the fused loop; for tests)."""
    n = state.shape[1]
    out = np.empty(n)
    for i in range(n):
        off = state[4, i] if state.shape[0] > 4 else 0.0
        out[i] = level_loglik_particle(state[0, i], state[1, i], state[2, i], state[3, i], off,
                                       level_db, ovx, ovy, ross, p0_db, xp, fp, xp.size,
                                       0.5 / (sigma_db * sigma_db))
    return out


@njit(cache=True, error_model="numpy")
def level_loglik_sd_arrays(state, level_db, ovx, ovy, ross, p0_db, xp, fp, sp, sigma_db):
    """Eq. 33 with the grid's K error sd profile ``sp`` for (D, N) particles (for tests)."""
    n = state.shape[1]
    out = np.empty(n)
    for i in range(n):
        off = state[4, i] if state.shape[0] > 4 else 0.0
        out[i] = level_loglik_particle_sd(state[0, i], state[1, i], state[2, i], state[3, i], off,
                                          level_db, ovx, ovy, ross, p0_db, xp, fp, sp, xp.size,
                                          sigma_db * sigma_db)
    return out


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def k_at_arrays(r, xp, fp):
    """`k_at` at each range of ``r`` (for tests)."""
    out = np.empty(r.size)
    for i in range(r.size):
        out[i] = k_at(r[i], xp, fp, xp.size)
    return out


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def init_arrays(g, z0, ovx, ovy, prior):
    """Prior particles (4, N) from normals ``g`` (4, N) and a `Prior`, as the fused loop."""
    n = g.shape[1]
    out = np.empty((4, n))
    for i in range(n):
        out[0, i], out[1, i], out[2, i], out[3, i] = init_particle(
            g[0, i], g[1, i], g[2, i], g[3, i], z0, ovx, ovy, prior)
    return out


@njit(cache=True, error_model="numpy")
def epanechnikov_draws(s, d, n):
    """``n`` kernel draws, shape (n, d) (for tests)."""
    eps = np.empty((d, n))
    fill_epanechnikov(s, eps, np.empty(n), np.empty(n))
    return eps.T.copy()


@njit(cache=True, error_model="numpy")
def resample_draw(w, s):
    """`resample_indices` for one weight vector (for tests)."""
    idx = np.empty(w.size, np.int64)
    resample_indices(w, s, np.empty(w.size), idx, np.empty(w.size + 1))
    return idx


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def summaries_arrays(state, w, ovx, ovy):
    """`particle_sds_run` of (D, N) particles (for tests)."""
    out = np.empty(3)
    particle_sds_run(state, w, ovx, ovy, out)
    return out

