"""Particle weights: normalisation with logsumexp (eq. 19) and the effective sample size
(eq. 20).

References
----------
E. Iglesis, L. de Montella (2024), eqs. 19-20.
"""

from __future__ import annotations

import numpy as np


def normalise(log_w: np.ndarray) -> np.ndarray:
    """Normalised log-weights along the last axis (eq. 19 with logsumexp)."""
    return normalise_exp(log_w.copy())[0]


def normalise_exp(log_w: np.ndarray, out: np.ndarray | None = None
                  ) -> tuple[np.ndarray, np.ndarray]:
    """In place: log-weights normalised along the last axis, and their exponentials (eq. 19).

    logsumexp by hand: shift by the row maximum, one exp, one sum, one log per row.

    Parameters
    ----------
    log_w : ndarray, shape (..., N)
        Log-weights, changed in place.
    out : ndarray, optional
        Where to put the weights.

    Returns
    -------
    log_w, w : ndarray, shape (..., N)
    """
    log_w -= log_w.max(axis=-1, keepdims=True)
    w = np.exp(log_w, out=out)
    total = w.sum(axis=-1, keepdims=True)
    w /= total
    log_w -= np.log(total)
    return log_w, w


def n_eff(weights: np.ndarray) -> np.ndarray:
    """Effective sample size 1 / sum w^2 along the last axis, eq. 20."""
    return 1.0 / np.einsum("...i,...i->...", weights, weights)
