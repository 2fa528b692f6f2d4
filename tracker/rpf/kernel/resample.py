"""Multinomial resampling of one run in the compiled kernel, as
`tracker.rpf.resample.multinomial_resample`."""

from __future__ import annotations

from numba import njit

from tracker.rpf.kernel.fastmath import FASTMATH
from tracker.rpf.kernel.random import fill_exponentials


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def resample_indices(w, s, cdf, idx, spac):
    """Multinomial draw of N indices with probabilities ``w`` into ``idx``, sorted: N sorted
    uniforms from normalised exponential spacings (``spac``, N + 1 long) walked along the
    cumulative sum (as `rpf.multinomial_resample`, ``searchsorted(side="right")``)."""
    n = w.size
    acc = 0.0
    for i in range(n):
        acc += w[i]
        cdf[i] = acc
    inv_cdf = 1.0 / acc
    for i in range(n):
        cdf[i] *= inv_cdf
    fill_exponentials(s, spac)
    total = 0.0
    for i in range(n + 1):
        total += spac[i]
        spac[i] = total
    inv = 1.0 / total
    j = 0
    for i in range(n):
        u = spac[i] * inv
        while j < n - 1 and cdf[j] <= u:
            j += 1
        idx[i] = j

