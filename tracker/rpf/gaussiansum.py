"""The posterior of the particle filter's own model on bearings, without sampling: a Gaussian sum
of extended Kalman filters, the reference that tells the filter's sampler from its model.

The filter's model on bearings alone is its prior (`tracker.rpf.prior.initial_particles`: range,
bearing, speed and course normal), its motion (eqs. 4-6, white acceleration of sd sigma_a) and
its bearing likelihood (eq. 32, each cycle's sd). Its posterior is what the particles sample.
Here the prior is written as a sum of Gaussians, one per node of a grid over first range, course
and speed (the first bearing the measured one, its spread the filter's sigma_theta), each node
weighted by the prior's density there; each Gaussian is carried through the cycles by an
extended Kalman filter with the model's process noise, which integrates the accelerations out
exactly for a linear measurement. A bearing is linear in the cross-range position to the
component's relative width (a few per cent of the range), so the sum's posterior is the model's
to that order, and every component's evidence (the probability of the bearings it was given)
weighs it (Alspach and Sorenson's Gaussian sum filter).

What it shows: with precise bearings and a range the bearings leave open (an observer that
keeps its course, a target on a constant bearing) the model's accelerations make a near target
less likely than a far one, whose random accelerations would move its bearings less
(`docs/depth.md`, "What makes them miss, measured"). That tilt is the model's, and no sampler
removes it.

References
----------
D. L. Alspach, H. W. Sorenson, "Nonlinear Bayesian estimation using Gaussian sum
approximations", IEEE Trans. Automatic Control 17 (1972) 439-448.
E. Iglesis, L. de Montella (2024), eqs. 4-6 and 32 (the model), sec. 5 (the prior).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tracker.rpf.config import RpfConfig
from tracker.rpf.weights import normalise_exp

#: Nodes over first range, course and speed, each spanning the prior's mean +- `SPAN_SD` sds.
GRID = (41, 37, 25)
SPAN_SD = 3.5
#: Each component's sd, as a fraction of its node's spacing: the sum is then a smooth density
#: (about 1 % wider in variance than the prior it stands for).
COMPONENT_SD_FRACTION = 0.6


@dataclass(frozen=True, slots=True)
class ModelPosterior:
    """The model's posterior of the range at every cycle (T,), m, and the log evidence of the
    bearings (their probability under the model, up to the constant of the bearings' sds)."""

    range_mean_m: np.ndarray
    range_sd_m: np.ndarray
    log_evidence: float


def _log_sum_exp(a: np.ndarray) -> float:
    top = float(a.max())
    return top + math.log(float(np.exp(a - top).sum()))


def _nodes(mean: float, sd: float, n: int) -> tuple[np.ndarray, float]:
    x = mean + sd * np.linspace(-SPAN_SD, SPAN_SD, n)
    return x, float(x[1] - x[0])


def _prior_components(cfg: RpfConfig, z0: float, obs_vel: np.ndarray, grid) -> tuple:
    """Means (N, 4), covariances (N, 4, 4) and log weights (N,) of the prior's Gaussian sum."""
    if cfg.range_span_m:
        raise ValueError("the Gaussian sum takes the normal range prior; range_span_m is set")
    r, dr = _nodes(cfg.range_mean_m, cfg.range_sd_m, grid[0])
    c, dc = _nodes(z0 + math.pi, math.radians(cfg.course_sd_deg), grid[1])
    s, ds = _nodes(cfg.speed_mean_mps, cfg.speed_sd_mps, grid[2])
    rr, cc, ss = (a.ravel() for a in np.meshgrid(r, c, s, indexing="ij"))
    log_w = (-0.5 * ((rr - cfg.range_mean_m) / cfg.range_sd_m) ** 2
             - 0.5 * ((cc - z0 - math.pi) / math.radians(cfg.course_sd_deg)) ** 2
             - 0.5 * ((ss - cfg.speed_mean_mps) / cfg.speed_sd_mps) ** 2)
    n = rr.size
    mean = np.stack([rr * math.sin(z0), rr * math.cos(z0),
                     ss * np.sin(cc) - obs_vel[0], ss * np.cos(cc) - obs_vel[1]], axis=1)
    cov = np.zeros((n, 4, 4))
    # position: range (the node's spread) and bearing (the filter's sigma_theta) to Cartesian
    var_r = (COMPONENT_SD_FRACTION * dr) ** 2
    var_t = math.radians(cfg.bearing_sigma_deg) ** 2
    jr = np.array([math.sin(z0), math.cos(z0)])
    jt = np.array([math.cos(z0), -math.sin(z0)])
    pos = var_r * np.outer(jr, jr)[None] + var_t * (rr ** 2)[:, None, None] * np.outer(jt, jt)[None]
    cov[:, :2, :2] = pos
    # velocity: speed and course (the nodes' spreads) to Cartesian
    js = np.stack([np.sin(cc), np.cos(cc)], axis=1)
    jc = np.stack([ss * np.cos(cc), -ss * np.sin(cc)], axis=1)
    cov[:, 2:, 2:] = ((COMPONENT_SD_FRACTION * ds) ** 2 * js[:, :, None] * js[:, None, :]
                      + (COMPONENT_SD_FRACTION * dc) ** 2 * jc[:, :, None] * jc[:, None, :])
    return mean, cov, log_w


def bearings_posterior(t_s: np.ndarray, obs_state: np.ndarray, bearing_rad: np.ndarray,
                       bearing_sd_rad: np.ndarray, cfg: RpfConfig, *, grid=GRID) -> ModelPosterior:
    """The filter's model's posterior of the range at every cycle, from one run's bearings.

    Parameters
    ----------
    t_s : ndarray, shape (T,)
        Cycle times, s.
    obs_state : ndarray, shape (T, 4)
        Observer (x, y, vx, vy), m and m/s.
    bearing_rad, bearing_sd_rad : ndarray, shape (T,)
        The bearings and their sds, rad (NaN bearing: none that cycle; NaN sd: the filter's
        sigma_theta). As in the filter, the first bearing places the prior and is not weighed.
    cfg : RpfConfig
        The filter's prior, sigma_a and sigma_theta.
    grid : tuple of int
        Nodes over first range, course and speed.
    """
    t_s = np.asarray(t_s, dtype=float)
    obs = np.asarray(obs_state, dtype=float)
    z = np.asarray(bearing_rad, dtype=float)
    sd = np.where(np.isfinite(bearing_sd_rad), bearing_sd_rad, math.radians(cfg.bearing_sigma_deg))
    m, p, log_w = _prior_components(cfg, float(z[0]), obs[0, 2:], grid)
    # the filter's acceleration sds (RpfConfig.sigma_a_mix_mps2): the components once per sd,
    # the particles' equal shares as equal prior weights
    mix = np.asarray(cfg.particle_sigma_a_mps2, dtype=float)
    var_a = np.repeat(mix ** 2, log_w.size)[:, None, None]
    m, p, log_w = np.tile(m, (mix.size, 1)), np.tile(p, (mix.size, 1, 1)), np.tile(log_w, mix.size)
    log_ev = np.zeros(log_w.size)
    mean_out = np.empty(t_s.size)
    sd_out = np.empty(t_s.size)
    for k in range(t_s.size):
        if k > 0:
            dt = t_s[k] - t_s[k - 1]
            f = np.eye(4)
            f[0, 2] = f[1, 3] = dt
            c = f @ obs[k - 1] - obs[k]  # the observer's own move, as in eq. 4
            q = np.array([[dt ** 4 / 4, dt ** 3 / 2], [dt ** 3 / 2, dt ** 2]])
            qq = np.zeros((4, 4))
            qq[np.ix_([0, 2], [0, 2])] = q
            qq[np.ix_([1, 3], [1, 3])] = q
            m = m @ f.T + c
            p = f @ p @ f.T + var_a * qq
            if math.isfinite(z[k]):
                r2 = m[:, 0] ** 2 + m[:, 1] ** 2
                h = np.zeros((m.shape[0], 4))
                h[:, 0], h[:, 1] = m[:, 1] / r2, -m[:, 0] / r2
                nu = (z[k] - np.arctan2(m[:, 0], m[:, 1]) + math.pi) % (2.0 * math.pi) - math.pi
                ph = np.einsum("nij,nj->ni", p, h)
                s = np.einsum("ni,ni->n", h, ph) + sd[k] ** 2
                gain = ph / s[:, None]
                m = m + gain * nu[:, None]
                p = p - gain[:, :, None] * ph[:, None, :]
                log_ev += -0.5 * (np.log(s / sd[k] ** 2) + nu * nu / s)
        w = normalise_exp(log_w + log_ev)[1]
        rng = np.hypot(m[:, 0], m[:, 1])
        u = m[:, :2] / rng[:, None]
        var = np.einsum("ni,nij,nj->n", u, p[:, :2, :2], u)
        mu = float(w @ rng)
        mean_out[k] = mu
        sd_out[k] = math.sqrt(float(w @ (var + (rng - mu) ** 2)))
    log_evidence = _log_sum_exp(log_w + log_ev) - _log_sum_exp(log_w)
    return ModelPosterior(range_mean_m=mean_out, range_sd_m=sd_out, log_evidence=log_evidence)
