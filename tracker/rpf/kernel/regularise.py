"""Regularization of one run in the compiled kernel (eqs. 21-28), as
`tracker.rpf.regularise.regularise`: the loaded Cholesky factor of the covariance, the
Epanechnikov kernel draws and the jitter x = x'_idx + h D eps."""

from __future__ import annotations

import math

from numba import njit

from tracker.rpf.kernel.fastmath import FASTMATH
from tracker.rpf.kernel.random import fill_exponentials, fill_normal_pairs


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def cholesky_loaded(cov, chol):
    """Lower Cholesky factor of ``cov`` + (1e-12 max diag + 1e-18) I, as `rpf.regularise`."""
    d = cov.shape[0]
    scale = 0.0
    for a in range(d):
        scale = max(scale, cov[a, a])
    load = 1e-12 * scale + 1e-18
    for a in range(d):
        for b in range(d):
            chol[a, b] = 0.0
    for j in range(d):
        acc = cov[j, j] + load
        for k in range(j):
            acc -= chol[j, k] * chol[j, k]
        diag = math.sqrt(max(acc, 0.0))
        chol[j, j] = diag
        for i in range(j + 1, d):
            acc = cov[i, j]
            for k in range(j):
                acc -= chol[i, k] * chol[j, k]
            chol[i, j] = acc / diag if diag > 0.0 else 0.0


@njit(inline="always")
def fill_epanechnikov(s, eps, e1, e2):
    """N draws of the Epanechnikov kernel on the unit ball of R^d into ``eps`` (d, N) (eq. 26):
    d normals over the root of their squared norm plus a chi^2_4 = 2 (E1 + E2); ``e1``, ``e2``
    (N,) are scratch."""
    d, n = eps.shape
    for a in range(0, d, 2):
        if a + 1 < d:
            fill_normal_pairs(s, eps[a], eps[a + 1])
        else:
            fill_normal_pairs(s, eps[a], e2)
    fill_exponentials(s, e1)
    fill_exponentials(s, e2)
    for i in range(n):
        e1[i] = 2.0 * (e1[i] + e2[i])
    for a in range(d):
        for i in range(n):
            e1[i] += eps[a, i] * eps[a, i]
    for i in range(n):
        e1[i] = 1.0 / math.sqrt(e1[i])
    for a in range(d):
        for i in range(n):
            eps[a, i] *= e1[i]


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def regularise_run(state, idx, mean, chol, eps, h, shrink, new):
    """Eq. 21 for one run into ``new`` (D, N): x = x'_idx + h D eps, or with ``shrink``
    x = m + a (x'_idx - m) + h D eps, a = sqrt(1 - h^2/(D+4)). ``eps`` is (D, N)."""
    d, n = state.shape
    a = math.sqrt(max(0.0, 1.0 - h * h / (d + 4))) if shrink else 1.0
    for r in range(d):
        src = state[r]
        dst = new[r]
        for i in range(n):
            dst[i] = src[idx[i]]
        if shrink:
            m = mean[r]
            for i in range(n):
                dst[i] = m + a * (dst[i] - m)
        for c in range(r + 1):
            hc = h * chol[r, c]
            e = eps[c]
            for i in range(n):
                dst[i] += hc * e[i]

