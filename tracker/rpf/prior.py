"""The filter's initial particles from the first bearing (Ristic et al. 2003, sec. 6.4.1.1,
as in the paper's sec. 5).

References
----------
B. Ristic, S. Arulampalam, N. Gordon, "Beyond the Kalman filter" (2003), sec. 6.4.1.1.
E. Iglesis, L. de Montella (2024), sec. 5.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.special import ndtr

from tracker.rpf.config import RpfConfig


def initial_particles(bearing0_rad, obs_vel_mps, cfg: RpfConfig, runs: int,
                      rng: np.random.Generator) -> np.ndarray:
    """Particles from the first bearing: range N(r, sd) (or log-uniform over
    ``cfg.range_span_m``), bearing N(z0, sigma_theta), speed N(s, sd), course N(z0 + pi, pi/sqrt 12).

    Parameters
    ----------
    bearing0_rad : array_like, shape (runs,) or scalar
        First bearing of each run, rad.
    obs_vel_mps : array_like, shape (2,)
        Observer velocity at the first cycle, m/s (the state is relative).
    cfg : RpfConfig
        Prior means and sds, N and the state dimension.
    runs : int
    rng : numpy.random.Generator
        Source of the D normals per particle.

    Returns
    -------
    state : ndarray, shape (D, runs, N)
    """
    n = cfg.n_particles
    z0 = np.broadcast_to(np.asarray(bearing0_rad, dtype=float), (runs,))[:, None]
    g = rng.standard_normal((cfg.n_dim, runs, n))
    state = np.empty((cfg.n_dim, runs, n))
    if cfg.range_span_m:  # the same normal draw through its CDF: log-uniform over the span
        near, far = np.log(cfg.range_span_m)
        rng_m = np.exp(near + (far - near) * ndtr(g[0]))
    else:
        rng_m = cfg.range_mean_m + cfg.range_sd_m * g[0]
    theta = z0 + math.radians(cfg.bearing_sigma_deg) * g[1]
    speed = cfg.speed_mean_mps + cfg.speed_sd_mps * g[2]
    course = z0 + math.pi + math.radians(cfg.course_sd_deg) * g[3]
    state[0] = rng_m * np.sin(theta)
    state[1] = rng_m * np.cos(theta)
    state[2] = speed * np.sin(course) - float(obs_vel_mps[0])
    state[3] = speed * np.cos(course) - float(obs_vel_mps[1])
    if cfg.n_dim > 4:
        state[4] = cfg.sl_offset_sd_db * g[4]
    return state
