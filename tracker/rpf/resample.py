"""Multinomial resampling of every run's particles at once (sec. 4.3, step 3).

References
----------
E. Iglesis, L. de Montella (2024), sec. 4.3.
"""

from __future__ import annotations

import numpy as np


def multinomial_resample(weights: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Indices of a multinomial draw of N particles with probabilities ``weights`` per row.

    Parameters
    ----------
    weights : ndarray, shape (runs, N)
        Normalised weights of each run.
    rng : numpy.random.Generator
        Source of the N + 1 exponentials per row.

    Returns
    -------
    idx : ndarray of int, shape (runs, N)
        Sorted draws; all rows searched at once by offsetting each row's CDF by its row number.
    """
    runs, n = weights.shape
    cdf = np.cumsum(weights, axis=1)
    cdf /= cdf[:, -1:]
    # n sorted uniforms per row from normalised exponential spacings
    e = rng.exponential(size=(runs, n + 1))
    u = np.cumsum(e, axis=1)
    u = np.divide(u[:, :-1], u[:, -1:], out=e[:, :-1])
    if runs == 1:
        idx = np.searchsorted(cdf[0], u[0], side="right")[None]
    else:
        offset = np.arange(runs, dtype=float)[:, None]
        cdf += offset
        u += offset
        flat = np.searchsorted(cdf.ravel(), u.ravel(), side="right")
        idx = flat.reshape(runs, n) - np.arange(runs)[:, None] * n
    return np.minimum(idx, n - 1, out=idx)
