"""Weights in the compiled kernel: logsumexp normalisation (eq. 19) and N_eff (eq. 20) of one
run, as `tracker.rpf.weights`."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from tracker.rpf.kernel.fastmath import FASTMATH, exp_nonpos


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def normalise_run(log_w, w):
    """In place: log-weights normalised (logsumexp, eq. 19), ``w`` their exponentials; N_eff
    (eq. 20) returned."""
    n = log_w.size
    top = -np.inf
    for i in range(n):
        if log_w[i] > top:
            top = log_w[i]
    total = 0.0
    for i in range(n):
        log_w[i] -= top
        e = exp_nonpos(log_w[i])
        w[i] = e
        total += e
    inv = 1.0 / total
    lt = math.log(total)
    sq = 0.0
    for i in range(n):
        wi = w[i] * inv
        w[i] = wi
        sq += wi * wi
        log_w[i] -= lt
    return 1.0 / sq

