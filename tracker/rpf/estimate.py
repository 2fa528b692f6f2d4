"""Estimate and covariance of the particle cloud (eqs. 29-30), and the particle spreads a
track file reports.

References
----------
E. Iglesis, L. de Montella (2024), eqs. 29-30.
"""

from __future__ import annotations

import numpy as np

from tracker.rpf.scratch import scratch


def weighted_covariance(state: np.ndarray, weights: np.ndarray, work: dict | None = None
                        ) -> tuple[np.ndarray, np.ndarray]:
    """Weighted mean (D, runs) and covariance (runs, D, D) of the particles, eqs. 29-30.

    Parameters
    ----------
    state : ndarray, shape (D, runs, N)
    weights : ndarray, shape (runs, N)
        Normalised weights.
    work : dict, optional
        Scratch arrays (`tracker.rpf.scratch`).
    """
    # each run's covariance is one (D, N) @ (N, D) product (strided views BLAS takes as they
    # are); all runs in one batched matmul
    mean = np.einsum("drn,rn->dr", state, weights)
    dev = np.subtract(state, mean[:, :, None], out=scratch(work, "dev", state.shape))
    dw = np.multiply(dev, weights, out=scratch(work, "dw", state.shape))
    cov = np.matmul(dev.transpose(1, 0, 2), dw.transpose(1, 2, 0))
    return mean, cov


def estimate(state: np.ndarray, weights: np.ndarray, work: dict | None = None
             ) -> tuple[np.ndarray, np.ndarray]:
    """Estimate x_hat (eq. 29), shape (D, runs), and covariance P_hat (eq. 30), (runs, D, D)."""
    return weighted_covariance(state, weights, work)


def particle_sds(state: np.ndarray, w: np.ndarray, obs_vel) -> np.ndarray:
    """Weighted sd of range (m), course (deg, circular) and target speed (m/s) per run.

    Parameters
    ----------
    state : ndarray, shape (D, runs, N)
        Relative state.
    w : ndarray, shape (runs, N)
        Normalised weights.
    obs_vel : array_like, shape (2,)
        Observer velocity, m/s (the target's is the relative one plus it).

    Returns
    -------
    sds : ndarray, shape (runs, 3)
        Range sd, m; circular course sd sqrt(-2 ln R), deg; speed sd, m/s.
    """
    r = np.hypot(state[0], state[1])
    vx = state[2] + float(obs_vel[0])
    vy = state[3] + float(obs_vel[1])
    speed = np.hypot(vx, vy)
    course = np.arctan2(vx, vy)

    def sd(a):
        m = np.einsum("rn,rn->r", a, w)
        return np.sqrt(np.maximum(np.einsum("rn,rn->r", (a - m[:, None]) ** 2, w), 0.0))

    c = np.einsum("rn,rn->r", np.cos(course), w)
    s = np.einsum("rn,rn->r", np.sin(course), w)
    resultant = np.clip(np.hypot(c, s), 1e-300, 1.0)
    course_sd = np.degrees(np.sqrt(-2.0 * np.log(resultant)))
    return np.stack([sd(r), course_sd, sd(speed)], axis=-1)
