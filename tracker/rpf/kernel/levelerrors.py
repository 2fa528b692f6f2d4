"""The levels' persistent errors integrated out per particle in the compiled kernel: each particle
carries the Gaussian posterior (mean, covariance) of the error components of
`tracker.levels.LevelErrors` along its own path, and its level likelihood is the exact marginal
one, as `tracker.levels.log_marginal` computes it along one path (a Rao-Blackwellised filter:
the components are linear and Gaussian given the particle's motion).

Arrays are component-major, ``mean`` (S, N) and ``cov`` (S, S, N), so that each pass over the
particles reads contiguous rows.
"""

from __future__ import annotations

import math

from numba import njit

from tracker.rpf.kernel.fastmath import FASTMATH


@njit(fastmath=FASTMATH, error_model="numpy")
def errors_init(mean, cov, var0):
    """Every particle's components at their prior: mean 0, covariance diag(``var0``) (S,)."""
    s, n = mean.shape
    for a in range(s):
        for i in range(n):
            mean[a, i] = 0.0
        for b in range(s):
            v = var0[a] if a == b else 0.0
            for i in range(n):
                cov[a, b, i] = v


@njit(fastmath=FASTMATH, error_model="numpy")
def errors_predict(mean, cov, dt, step_m, inv_time, inv_length, var_prev, var_now, rho):
    """Bring each particle's components from the last cycle to this one: a residual forgets by
    rho = exp(-dt / time - ``step_m`` / length), ``step_m`` the target's move relative to the
    observer since the last cycle as the run's estimate has it (the same for every particle: a
    correlation along each particle's own path would weigh the particles by how well their own
    relative speed fits the residual's roughness, a pull on the speed that the levels do not
    carry); each variance is then raised to this cycle's prior (an offset's growth by
    independent increments). ``rho`` (S,) is scratch."""
    s, n = mean.shape
    for a in range(s):
        rho[a] = math.exp(-dt * inv_time[a] - step_m * inv_length[a])
    for a in range(s):
        add = max(var_now[a] - rho[a] * rho[a] * var_prev[a], 0.0)
        for i in range(n):
            mean[a, i] *= rho[a]
        for b in range(s):
            f = rho[a] * rho[b]
            for i in range(n):
                cov[a, b, i] *= f
        for i in range(n):
            cov[a, a, i] += add


@njit(inline="always")
def errors_update_particle(mean, cov, i, h, resid, var_n, ph):
    """One band's level at particle ``i``: the innovation ``resid`` - h mean, its variance
    h P h^T + ``var_n``; the components updated; ln of the innovation's density returned (the
    constant -ln(2 pi) / 2 left out). ``h`` (S,) the band's loadings, ``ph`` (S,) scratch."""
    s = h.size
    innov = resid
    for a in range(s):
        innov -= h[a] * mean[a, i]
    for a in range(s):
        acc = 0.0
        for b in range(s):
            acc += cov[a, b, i] * h[b]
        ph[a] = acc
    var = var_n
    for a in range(s):
        var += h[a] * ph[a]
    inv = 1.0 / var
    for a in range(s):
        mean[a, i] += ph[a] * innov * inv
    for a in range(s):
        for b in range(s):
            cov[a, b, i] -= ph[a] * ph[b] * inv
    return -0.5 * (innov * innov * inv + math.log(var))


@njit(fastmath=FASTMATH, error_model="numpy")
def errors_copy(mean, cov, idx, mean_new, cov_new):
    """The resampled particles' components: row ``idx[i]`` into row ``i`` of the new arrays."""
    s, n = mean.shape
    for a in range(s):
        for i in range(n):
            mean_new[a, i] = mean[a, idx[i]]
        for b in range(s):
            for i in range(n):
                cov_new[a, b, i] = cov[a, b, idx[i]]
