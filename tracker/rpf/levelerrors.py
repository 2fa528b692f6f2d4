"""The levels' persistent errors integrated out per particle, numpy reference of
`tracker.rpf.kernel.levelerrors`: each particle's Gaussian posterior over the error components
of `tracker.levels.LevelErrors`, brought along the path and updated by each band's level; its
level likelihood is the innovation's density (the exact marginal likelihood, as
`tracker.levels.log_marginal` computes it along one path). The covariance is the same for every
particle of a run (it does not depend on the levels): one per run, the particles' means apart."""

from __future__ import annotations

import numpy as np

from tracker.levels import cycle_prior_variance


class ParticleErrors:
    """The components' means (S, runs, N) of a block's particles and each run's covariance
    (S, S, runs).

    Parameters
    ----------
    level_errors : tracker.levels.LevelErrors
    n_bands, n_cycles : int
    shape : (runs, N)
    displacement_m : array_like, shape (K,), optional
        The observer's distance from where the tables were computed, m (default 0).
    """

    def __init__(self, level_errors, n_bands: int, n_cycles: int, shape, displacement_m=None):
        a = level_errors.arrays(n_bands)
        self.h = a["h"]                                                   # (B, S)
        self.var = cycle_prior_variance(a, n_cycles, displacement_m)     # (K, S)
        self.inv_time, self.inv_length = a["inv_time_s"], a["inv_length_m"]
        s = self.h.shape[1]
        self.mean = np.zeros((s,) + tuple(shape))
        self.cov = np.zeros((s, s, shape[0]))
        for j in range(s):
            self.cov[j, j] = self.var[0, j]

    def predict(self, k: int, dt: float, step_m: np.ndarray) -> None:
        """From cycle k - 1 to k: residuals forget by exp(-dt / time - step / length), ``step_m``
        (runs,) the target's move relative to the observer as each run's estimate has it (the
        same for its particles, `tracker.rpf.kernel.levelerrors.errors_predict` says why);
        variances raised to cycle k's prior."""
        step = np.asarray(step_m, dtype=float)[None, :]
        rho = np.exp(-dt * self.inv_time[:, None] - step * self.inv_length[:, None])      # (S, runs)
        self.mean *= rho[:, :, None]
        self.cov *= rho[:, None] * rho[None, :]
        for j in range(self.h.shape[1]):
            self.cov[j, j] += np.maximum(self.var[k, j] - rho[j] ** 2 * self.var[k - 1, j], 0.0)

    def update(self, band: int, resid_db: np.ndarray, have: np.ndarray, var_n: float) -> np.ndarray:
        """One band's level: ``resid_db`` (runs, N) the level less each particle's prediction,
        ``have`` (runs, 1) the runs with a level; returns the log-likelihood increments (runs, N)
        (0 where no level; the constant -ln(2 pi) / 2 left out) and updates the components."""
        h = self.h[band]
        resid = np.where(have, resid_db, 0.0)
        innov = resid - np.einsum("s,srn->rn", h, self.mean)
        ph = np.einsum("str,t->sr", self.cov, h)                                          # (S, runs)
        var = var_n + np.einsum("s,sr->r", h, ph)                                         # (runs,)
        gain = np.where(have[:, 0], ph / var, 0.0)                                        # (S, runs)
        self.mean += gain[:, :, None] * innov
        self.cov -= gain[:, None] * ph[None, :]
        # the variance is the run's: its log, a constant of the cycle, drops out of the weights
        return np.where(have, -0.5 * innov * innov / var[:, None], 0.0)

    def resample(self, rows: np.ndarray, idx: np.ndarray) -> None:
        """The resampled runs ``rows`` (runs,) bool: particle i takes particle ``idx[:, i]``'s
        components (``idx`` (rows, N), indices within each run)."""
        sel = np.flatnonzero(rows)
        mean = self.mean[:, sel]
        self.mean[:, sel] = np.take_along_axis(mean, np.broadcast_to(idx, mean.shape), axis=-1)


__all__ = ["ParticleErrors"]
