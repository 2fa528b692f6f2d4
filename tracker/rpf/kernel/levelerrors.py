"""The levels' persistent errors integrated out per particle in the compiled kernel: each particle
carries the Gaussian posterior of the error components of `tracker.levels.LevelErrors` along its
own path, and its level likelihood is the exact marginal one, as `tracker.levels.log_marginal`
computes it along one path (a Rao-Blackwellised filter: the components are linear and Gaussian
given the particle's motion).

The Kalman filter's covariance does not depend on the levels, only on the loadings, the
measurement's variance and the forgetting, which are the same for every particle of a run (the
residual forgets along the run's estimated relative move): one covariance ``cov`` (S, S) serves
the run, the particles differing by their means ``mean`` (S, N) alone. The innovation's variance
is then the same for every particle, so its log, a constant of the cycle, drops out of the
normalised weights and is left out.
"""

from __future__ import annotations

import math

from numba import njit

from tracker.rpf.kernel.fastmath import FASTMATH


@njit(fastmath=FASTMATH, error_model="numpy")
def errors_init(mean, cov, var0):
    """Every particle's components at their prior: mean 0, the run's covariance diag(``var0``) (S,)."""
    s, n = mean.shape
    for a in range(s):
        for i in range(n):
            mean[a, i] = 0.0
        for b in range(s):
            cov[a, b] = var0[a] if a == b else 0.0


@njit(fastmath=FASTMATH, error_model="numpy")
def errors_predict(mean, cov, dt, step_m, inv_time, inv_length, var_prev, var_now, rho):
    """Bring the components from the last cycle to this one: a residual forgets by
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
        if rho[a] != 1.0:
            r = rho[a]
            for i in range(n):
                mean[a, i] *= r
        for b in range(s):
            cov[a, b] *= rho[a] * rho[b]
    for a in range(s):
        cov[a, a] += max(var_now[a] - rho[a] * rho[a] * var_prev[a], 0.0)


@njit(fastmath=FASTMATH, error_model="numpy")
def errors_gain(cov, h, var_n, ph, gain):
    """One band's level: the innovation's variance h P h^T + ``var_n``, returned, and the gain
    P h^T / variance into ``gain`` (S,); the covariance updated, P - P h^T h P / variance (the
    same for every particle). ``ph`` (S,) is scratch."""
    s = h.size
    for a in range(s):
        acc = 0.0
        for b in range(s):
            acc += cov[a, b] * h[b]
        ph[a] = acc
    var = var_n
    for a in range(s):
        var += h[a] * ph[a]
    inv = 1.0 / var
    for a in range(s):
        gain[a] = ph[a] * inv
    for a in range(s):
        for b in range(s):
            cov[a, b] -= ph[a] * ph[b] * inv
    return var


@njit(inline="always")
def errors_update_particle(mean, i, h, resid, gain, half_inv_var):
    """Particle ``i``'s level: its innovation ``resid`` - h mean_i, the mean updated by the gain
    (`errors_gain`), ln of the innovation's density up to the cycle's constant returned."""
    s = h.size
    innov = resid
    for a in range(s):
        innov -= h[a] * mean[a, i]
    for a in range(s):
        mean[a, i] += gain[a] * innov
    return -(innov * innov) * half_inv_var


@njit(fastmath=FASTMATH, error_model="numpy")
def errors_copy(mean, idx, mean_new):
    """The resampled particles' components: row ``idx[i]`` into row ``i`` of the new means."""
    s, n = mean.shape
    for a in range(s):
        for i in range(n):
            mean_new[a, i] = mean[a, idx[i]]
