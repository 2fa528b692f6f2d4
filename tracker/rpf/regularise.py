"""Regularization after resampling: the Epanechnikov kernel, its MISE-optimal bandwidth and
the jitter x = x' + h D eps, eqs. 21-28.

References
----------
E. Iglesis, L. de Montella (2024), eqs. 21-28. C. Musso, N. Oudjane, F. Le Gland, "Improving
regularised particle filters" (2001).
"""

from __future__ import annotations

import math

import numpy as np

from tracker.rpf.estimate import weighted_covariance
from tracker.rpf.normals import standard_normal_pairs
from tracker.rpf.resample import multinomial_resample
from tracker.rpf.scratch import scratch


def unit_ball_volume(n_dim: int) -> float:
    """c_n, the volume of the unit ball in R^n: pi^(n/2) / Gamma(n/2 + 1)."""
    return math.pi ** (n_dim / 2.0) / math.gamma(n_dim / 2.0 + 1.0)


def optimal_bandwidth(n_particles: int, n_dim: int) -> float:
    """MISE-optimal bandwidth of the Epanechnikov kernel, eqs. 27-28.

    h = A(K) N^(-1/(n+4)),  A(K) = (8 c_n^-1 (n + 4) (2 sqrt(pi))^n)^(1/(n+4)).
    """
    a = (8.0 / unit_ball_volume(n_dim) * (n_dim + 4) * (2.0 * math.sqrt(math.pi)) ** n_dim
         ) ** (1.0 / (n_dim + 4))
    return a * n_particles ** (-1.0 / (n_dim + 4))


def epanechnikov_sample(n_dim: int, size, rng: np.random.Generator, work: dict | None = None
                        ) -> np.ndarray:
    """Draws from the Epanechnikov kernel on the unit ball of R^n (eq. 26).

    The first n coordinates of a point uniform on the unit sphere of R^(n+4) are uniform in the
    ball of R^(n+2), whose projection on R^n has density proportional to 1 - |x|^2: the
    Epanechnikov kernel. So: n + 4 normals, scaled by their norm, first n kept. The 4 dropped
    normals enter only through their squared norm, a chi^2 with 4 degrees of freedom, drawn as
    2 (E1 + E2) with E standard exponentials.

    Parameters
    ----------
    n_dim : int
        n.
    size : int or tuple of int
        Shape of the draws per coordinate.
    rng : numpy.random.Generator
    work : dict, optional
        Scratch arrays (`tracker.rpf.scratch`).

    Returns
    -------
    eps : ndarray, shape (n_dim, *size)
    """
    size = (size,) if np.isscalar(size) else tuple(size)
    g = np.empty((n_dim, *size))
    for i in range(0, n_dim, 2):
        a, b = standard_normal_pairs(size, rng, work)
        g[i] = a
        if i + 1 < n_dim:
            g[i + 1] = b
    e = rng.standard_exponential((2, *size))
    norm2 = np.add(e[0], e[1], out=e[0])
    norm2 *= 2.0
    norm2 += np.einsum("i...,i...->...", g, g)
    np.sqrt(norm2, out=norm2)
    g /= norm2
    return g


def regularise(state: np.ndarray, weights: np.ndarray, rng: np.random.Generator, *,
               bandwidth: float | None = None, shrink: bool = False,
               work: dict | None = None, indices: bool = False):
    """Resample then jitter with the Epanechnikov kernel, eq. 21: x = x' + h D eps.

    Parameters
    ----------
    state : ndarray, shape (D, runs, N)
        Particles before resampling.
    weights : ndarray, shape (runs, N)
        Their normalised weights.
    rng : numpy.random.Generator
        Source of the resampling draws, then of the kernel draws.
    bandwidth : float, optional
        h; default the optimal one of eqs. 27-28 for N and D.
    shrink : bool
        Variance-preserving form (not in the paper): x = m + a (x' - m) + h D eps with m the
        weighted mean and a = sqrt(1 - h^2/(n+4)); the kernel's covariance is I/(n+4).
    work : dict, optional
        Scratch arrays (`tracker.rpf.scratch`).
    indices : bool
        Also return which particle each new one was drawn from.

    Returns
    -------
    new_state : ndarray, shape (D, runs, N)
        Resampled, regularized particles (equal weights 1/N).
    idx : ndarray of int, shape (runs, N)
        With ``indices``: the particle of its run each new one was drawn from.

    Notes
    -----
    D is the Cholesky factor of the weighted empirical covariance P_k of the particles before
    resampling (Musso et al.); a tiny diagonal load keeps it defined when P_k is singular.
    """
    n_dim, runs, n = state.shape
    h = optimal_bandwidth(n, n_dim) if bandwidth is None else bandwidth
    mean, cov = weighted_covariance(state, weights, work)
    scale = np.maximum(np.einsum("rii->ri", cov), 0.0).max(axis=1)
    cov = cov + (1e-12 * scale + 1e-18)[:, None, None] * np.eye(n_dim)
    d = np.linalg.cholesky(cov)  # (runs, D, D)
    local = multinomial_resample(weights, rng)
    idx = local + (np.arange(runs) * n)[:, None]  # flat index into the (D, runs * N) particles
    new = np.take(state.reshape(n_dim, runs * n), idx.ravel(), axis=1).reshape(state.shape)
    if shrink:
        a = math.sqrt(max(0.0, 1.0 - h * h / (n_dim + 4)))
        m = mean[:, :, None]
        new -= m
        new *= a
        new += m
    eps = epanechnikov_sample(n_dim, (runs, n), rng, work)
    d *= h
    tmp = scratch(work, "tmp", (runs, n))
    for i in range(n_dim):  # new += h D eps, D lower triangular
        for j in range(i + 1):
            new[i] += np.multiply(d[:, i, j, None], eps[j], out=tmp)
    return (new, local) if indices else new
