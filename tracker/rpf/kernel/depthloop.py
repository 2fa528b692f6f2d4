"""The compiled cycle loop with the target's depth as a state (numba).

The loop of `tracker.rpf.kernel.loop` with these changes, in `tracker.rpf.kernel.depth` and
`tracker.rpf.kernel.depthmoments`:

- the last state component is the target's depth, m: its prior uniform over the span of
  `DepthModel`, its motion a slow random walk (sd ``walk_m_per_sqrt_s`` sqrt(dt)) with reflecting
  walls at the span's ends, and it is regularized with the other components (the particles'
  covariance carries the range-depth trade-off) then folded back into the span;
- the walk and the level likelihood (eq. 33) run as one pass (`walk_level_pass`), K at the
  particle's new depth, range and the cycle's bearing from the (depth, range) slabs of
  `DepthTable`, bilinear, the cells by index arithmetic on regular axes;
- the generator draws 1 more normal per particle and cycle (the walk; `fill_normals`);
- the moments take one pass for D = 6 (`moments_depth_run`).

Everything else (prediction, bearings, weights, resampling, regularization, estimates) is the
same code as the fixed-depth loop's. Its cost, side by side with that loop: docs/depth.md.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from tracker.rpf.kernel.depth import reflect_pass, walk_level_pass, walk_pass
from tracker.rpf.kernel.depthmoments import moments_depth_run
from tracker.rpf.kernel.estimate import particle_sds_run
from tracker.rpf.kernel.fastmath import FASTMATH
from tracker.rpf.kernel.likelihood import bearing_pass
from tracker.rpf.kernel.motion import predict_pass
from tracker.rpf.kernel.params import Measured, Outputs
from tracker.rpf.kernel.prior import init_particle
from tracker.rpf.kernel.random import fill_normal_pairs, fill_normals, normal_pair, uniform
from tracker.rpf.kernel.regularise import cholesky_loaded, fill_epanechnikov, regularise_run
from tracker.rpf.kernel.resample import resample_indices
from tracker.rpf.kernel.weights import normalise_run


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def run_one_depth(s, observer, measured, table, depth, prior, model, settings, out):
    """The filter over every cycle for one run, the depth the last state component.

    Parameters as `tracker.rpf.kernel.loop.run_one`, and ``table`` (a `DepthTable`: K against
    depth and range per radial, each cycle's radials) and ``depth`` (a `DepthModel`) in place
    of the K profiles.
    """
    t_s, obs = observer.t_s, observer.state
    bearing, level = measured.bearing_rad, measured.level_db
    sigma_a, use_level, ross, p0_db = model.sigma_a_mps2, model.use_level, model.ross, model.p0_db
    n, d, n_thr, h = settings.n, settings.d, settings.n_thr, settings.bandwidth
    iz = d - 1  # the depth's component
    io = 4 if d > 5 else -1  # the source-level offset's, if any
    lo, hi = depth.lo_m, depth.hi_m
    n_cycles = t_s.size
    state = np.empty((d, n))
    log_w = np.empty(n)
    w = np.empty(n)
    cdf = np.empty(n)
    idx = np.empty(n, np.int64)
    new = np.empty((d, n))
    eps = np.empty((d, n))
    spac = np.empty(n + 1)
    mean = np.empty(d)
    cov = np.empty((d, d))
    chol = np.empty((d, d))
    gx = np.zeros(n)
    gy = np.zeros(n)
    gz = np.zeros(n)
    half_b = 0.5 / (model.sigma_theta_rad * model.sigma_theta_rad)
    half_l = 0.5 / (model.sigma_l_db * model.sigma_l_db)
    log_n = -math.log(n)

    z0 = bearing[0]
    ovx0, ovy0 = obs[0, 2], obs[0, 3]
    for i in range(n):
        g0, g1 = normal_pair(s)
        g2, g3 = normal_pair(s)
        state[0, i], state[1, i], state[2, i], state[3, i] = init_particle(
            g0, g1, g2, g3, z0, ovx0, ovy0, prior)
        if d > 5:
            state[4, i] = prior.offset_sd_db * normal_pair(s)[0]
        state[iz, i] = lo + (hi - lo) * uniform(s)
        log_w[i] = log_n

    for k in range(n_cycles):
        has_b = k > 0 and not math.isnan(bearing[k])
        has_l = use_level and not math.isnan(level[k])
        moving = k > 0
        if moving:
            dt = t_s[k] - t_s[k - 1]
            dv_scale = dt * sigma_a
            cpx = obs[k - 1, 0] + dt * obs[k - 1, 2] - obs[k, 0]
            cpy = obs[k - 1, 1] + dt * obs[k - 1, 3] - obs[k, 1]
            cvx = obs[k - 1, 2] - obs[k, 2]
            cvy = obs[k - 1, 3] - obs[k, 3]
        else:
            dt = dv_scale = cpx = cpy = cvx = cvy = 0.0
        cz = math.cos(bearing[k]) if has_b else 1.0
        sz = math.sin(bearing[k]) if has_b else 0.0
        lv = level[k] if has_l else 0.0
        ovx, ovy = obs[k, 2], obs[k, 3]
        j0, j1, w1 = table.j0[k], table.j1[k], table.w1[k]

        if moving and sigma_a > 0.0:
            fill_normal_pairs(s, gx, gy)
        if moving:
            predict_pass(state[0], state[2], gx, dt, dv_scale, cpx, cvx)
            predict_pass(state[1], state[3], gy, dt, dv_scale, cpy, cvy)
        step_sd = depth.walk_m_per_sqrt_s * math.sqrt(dt) if moving and dt > 0.0 else 0.0
        if step_sd > 0.0:
            fill_normals(s, gz)
        if has_b:
            bearing_pass(state[0], state[1], log_w, cz, sz, half_b)
        if has_l:  # the walk and the level likelihood at the new depth in one pass
            walk_level_pass(state, iz, io, log_w, gz, step_sd, lo, hi, lv, ovx, ovy, ross, p0_db,
                            table, j0, j1, w1, half_l)
        elif step_sd > 0.0:
            walk_pass(state[iz], gz, step_sd, lo, hi)

        neff = normalise_run(log_w, w)
        moments_depth_run(state, w, mean, cov)
        if neff < n_thr:
            cholesky_loaded(cov, chol)
            resample_indices(w, s, cdf, idx, spac)
            fill_epanechnikov(s, eps, gx, gy)  # the process noise arrays as scratch
            regularise_run(state, idx, mean, chol, eps, h, settings.shrink, new)
            state, new = new, state
            reflect_pass(state[iz], lo, hi)
            for i in range(n):
                log_w[i] = log_n
                w[i] = 1.0 / n
            moments_depth_run(state, w, mean, cov)
            out.resampled[k] = 1
        for a in range(d):
            out.means[k, a] = mean[a]
            for b in range(d):
                out.covs[k, a, b] = cov[a, b]
        if settings.summaries:
            particle_sds_run(state, w, ovx, ovy, out.sds[k])


@njit(cache=True, nogil=True, error_model="numpy")
def run_runs_depth(states, observer, measured, table, depth, prior, model, settings, out):
    """`run_one_depth` for each run of a block in turn (as `tracker.rpf.kernel.loop.run_runs`)."""
    for r in range(states.shape[0]):
        run_one_depth(states[r], observer,
                      Measured(measured.bearing_rad[r], measured.level_db[r]), table, depth, prior,
                      model, settings,
                      Outputs(out.means[r], out.covs[r], out.resampled[r], out.sds[r]))
