"""The compiled, fused cycle loop of the regularized particle filter (numba).

`tracker.rpf.batch` (numpy) is the reference implementation; this loop runs the same
algorithm, eq. for eq., one run at a time with every particle of a cycle handled in a few
passes over data that stay in the core's cache:

1. the process noise (2 normals per particle, drawn in sequence from the run's generator,
   `tracker.rpf.kernel.random`);
2. prediction (eqs. 4-6, discrete white-noise acceleration), one loop per axis
   (`tracker.rpf.kernel.motion`); with the levels' errors integrated out, each particle's error
   components brought to this cycle along the run's estimated relative move
   (`tracker.rpf.kernel.levelerrors`);
3. bearing log-likelihood (eq. 32; residual in (-pi, pi] as the atan2 of the particle position
   rotated by -theta) added to the log-weights (`tracker.rpf.kernel.likelihood`);
4. SPL log-likelihood (eq. 33, h_l = SL(v) + K(r) of eqs. 12-16, or the constant P0) of each
   band with a level that cycle, K(r) by the `tables.LevelProfile` rule (`Profiles`): white
   with sigma_l (the paper's), or, with `Errors` on, the exact marginal likelihood of the level
   with the persistent and along-track errors of `tracker.levels.LevelErrors` integrated out,
   each particle's own Kalman update (`tracker.rpf.kernel.levelerrors`);
5. logsumexp normalisation (eq. 19), N_eff (eq. 20), weighted mean and covariance (eqs. 29-30)
   (`tracker.rpf.kernel.weights`, `tracker.rpf.kernel.estimate`);
6. when N_eff < N_thr: multinomial resampling (cumulative sum + sorted uniforms), optional
   shrinkage toward the mean, regularization x = x' + h D eps with the Epanechnikov kernel
   (eqs. 21-28), the resampled particles' error components copied with them, then mean and
   covariance again with equal weights (`tracker.rpf.kernel.resample`,
   `tracker.rpf.kernel.regularise`).

The loops of 2, 3 and 5 call no library function (`tracker.rpf.kernel.fastmath`), so LLVM
vectorizes them. Fast-math allows reassociation, so sums differ from numpy's in the last bits.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from tracker.rpf.kernel.estimate import moments_run, particle_sds_run
from tracker.rpf.kernel.fastmath import FASTMATH
from tracker.rpf.kernel.levelerrors import errors_copy, errors_gain, errors_init, errors_predict, errors_update_particle
from tracker.rpf.kernel.likelihood import (
    bearing_pass,
    level_loglik_particle,
    level_loglik_particle_sd,
    level_prediction_particle,
)
from tracker.rpf.kernel.motion import predict_pass
from tracker.rpf.kernel.params import Measured, Outputs
from tracker.rpf.kernel.prior import init_particle
from tracker.rpf.kernel.random import fill_normal_pairs, normal_pair
from tracker.rpf.kernel.regularise import cholesky_loaded, fill_epanechnikov, regularise_run
from tracker.rpf.kernel.resample import resample_indices
from tracker.rpf.kernel.weights import normalise_run


@njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def run_one(s, observer, measured, profiles, errors, prior, model, settings, out):
    """The filter over every cycle for one run.

    Parameters
    ----------
    s : ndarray of uint64, shape (4,)
        The run's generator state (`tracker.rpf.kernel.random`), advanced in place.
    observer : Observer
        Cycle times and observer track.
    measured : Measured
        The run's bearings and their sds (K,) and band levels (K, B).
    profiles : Profiles
        K(r) of each cycle and band.
    errors : Errors
        The levels' error components integrated out per particle (``errors.on``), else none.
    prior : Prior
    model : Model
    settings : Settings
        ``d`` counts the source-level offset (component 4) when present.
    out : Outputs
        The run's rows: ``means`` (K, D), ``covs`` (K, D, D), ``resampled`` (K,) uint8,
        ``sds`` (K, 3) or (1, 3); written.
    """
    t_s, obs = observer.t_s, observer.state
    bearing, level = measured.bearing_rad, measured.level_db
    use_level, ross, p0_db = model.use_level, model.ross, model.p0_db
    n, d, n_thr, h = settings.n, settings.d, settings.n_thr, settings.bandwidth
    io = 4 if d > 4 else -1  # the source-level offset's component, if any
    n_bands = level.shape[1]
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
    # each particle's acceleration sd, carried through resampling, and dt times it
    sigma_a = np.empty(n)
    sigma_a_new = np.empty(n)
    dv_scale = np.empty(n)
    n_mix = model.sigma_a_mps2.size
    noise = False
    for i in range(n):
        sigma_a[i] = model.sigma_a_mps2[i % n_mix]
        noise = noise or sigma_a[i] > 0.0
    var_l = model.sigma_l_db * model.sigma_l_db
    half_l = 0.5 / var_l
    log_n = -math.log(n)
    # the levels' error components: each particle's means (S, N), the run's covariance (S, S);
    # S = 0 without
    n_err = errors.h.shape[1] if errors.on else 0
    e_mean = np.zeros((n_err, n))
    e_cov = np.zeros((n_err, n_err))
    e_mean_new = np.zeros((n_err, n))
    rho = np.ones(n_err)
    ph = np.empty(n_err)
    gain = np.empty(n_err)

    z0 = bearing[0]
    ovx0, ovy0 = obs[0, 2], obs[0, 3]
    for i in range(n):
        g0, g1 = normal_pair(s)
        g2, g3 = normal_pair(s)
        state[0, i], state[1, i], state[2, i], state[3, i] = init_particle(
            g0, g1, g2, g3, z0, ovx0, ovy0, prior)
        if io >= 0:
            state[io, i] = prior.offset_sd_db * normal_pair(s)[0]
        log_w[i] = log_n
    if errors.on:
        errors_init(e_mean, e_cov, errors.var[0])

    for k in range(n_cycles):
        has_b = k > 0 and not math.isnan(bearing[k])
        moving = k > 0
        if moving:
            dt = t_s[k] - t_s[k - 1]
            for i in range(n):
                dv_scale[i] = dt * sigma_a[i]
            cpx = obs[k - 1, 0] + dt * obs[k - 1, 2] - obs[k, 0]
            cpy = obs[k - 1, 1] + dt * obs[k - 1, 3] - obs[k, 1]
            cvx = obs[k - 1, 2] - obs[k, 2]
            cvy = obs[k - 1, 3] - obs[k, 3]
        else:
            dt = cpx = cpy = cvx = cvy = 0.0
        cz = math.cos(bearing[k]) if has_b else 1.0
        sz = math.sin(bearing[k]) if has_b else 0.0
        sd_b = measured.bearing_sd_rad[k]
        half_b = 0.5 / (sd_b * sd_b) if has_b else 0.0
        ovx, ovy = obs[k, 2], obs[k, 3]

        # pass 1: process noise (sequential generator), then prediction and bearing
        # likelihood in one loop free of calls (it vectorizes), then the level likelihood
        if moving and noise:
            fill_normal_pairs(s, gx, gy)
        if moving:
            predict_pass(state[0], state[2], gx, dt, dv_scale, cpx, cvx)
            predict_pass(state[1], state[3], gy, dt, dv_scale, cpy, cvy)
            if errors.on:  # the run's estimated relative move since the last cycle
                step = dt * math.sqrt(mean[2] * mean[2] + mean[3] * mean[3])
                errors_predict(e_mean, e_cov, dt, step, errors.inv_time_s, errors.inv_length_m,
                               errors.var[k - 1], errors.var[k], rho)
        if has_b:
            bearing_pass(state[0], state[1], log_w, cz, sz, half_b)
        for b in range(n_bands):
            if not use_level or math.isnan(level[k, b]):
                continue
            lv = level[k, b]
            p = profiles.index[b, k]
            m = profiles.length[p]
            xp = profiles.range_m[p]
            fp = profiles.k_db[p]
            if errors.on:  # the exact marginal likelihood, each particle's components updated
                hb = errors.h[b]
                half = 0.5 / errors_gain(e_cov, hb, var_l, ph, gain)
                for i in range(n):
                    pred = level_prediction_particle(state[0, i], state[1, i], state[2, i], state[3, i],
                                                     ovx, ovy, ross, p0_db, xp, fp, m)
                    log_w[i] += errors_update_particle(e_mean, i, hb, lv - pred, gain, half)
            elif profiles.has_sd:  # the grid's K error sd at each particle's range
                sp = profiles.k_sd_db[p]
                for i in range(n):
                    off = state[io, i] if io >= 0 else 0.0
                    log_w[i] += level_loglik_particle_sd(state[0, i], state[1, i], state[2, i],
                                                         state[3, i], off, lv, ovx, ovy, ross, p0_db,
                                                         xp, fp, sp, m, var_l)
            else:
                for i in range(n):
                    off = state[io, i] if io >= 0 else 0.0
                    log_w[i] += level_loglik_particle(state[0, i], state[1, i], state[2, i],
                                                      state[3, i], off, lv, ovx, ovy, ross, p0_db,
                                                      xp, fp, m, half_l)

        # pass 2-3: weights, N_eff, mean and covariance (the covariance also feeds eq. 21)
        neff = normalise_run(log_w, w)
        moments_run(state, w, mean, cov)
        if neff < n_thr:
            cholesky_loaded(cov, chol)
            resample_indices(w, s, cdf, idx, spac)
            fill_epanechnikov(s, eps, gx, gy)  # the process noise arrays as scratch
            regularise_run(state, idx, mean, chol, eps, h, settings.shrink, new)
            state, new = new, state
            if n_mix > 1:
                for i in range(n):
                    sigma_a_new[i] = sigma_a[idx[i]]
                sigma_a, sigma_a_new = sigma_a_new, sigma_a
            if errors.on:
                errors_copy(e_mean, idx, e_mean_new)
                e_mean, e_mean_new = e_mean_new, e_mean
            for i in range(n):
                log_w[i] = log_n
                w[i] = 1.0 / n
            moments_run(state, w, mean, cov)
            out.resampled[k] = 1
        for a in range(d):
            out.means[k, a] = mean[a]
            for b in range(d):
                out.covs[k, a, b] = cov[a, b]
        if settings.summaries:
            particle_sds_run(state, w, ovx, ovy, out.sds[k])


@njit(cache=True, nogil=True, error_model="numpy")
def run_runs(states, observer, measured, profiles, errors, prior, model, settings, out):
    """`run_one` for each run of a block in turn.

    ``states`` (runs, 4) uint64 holds one generator state per run; ``measured`` and ``out``
    have a leading ``runs`` axis, the other groups are shared. Releases the GIL:
    `tracker.rpf.batch.run_batch` runs blocks of runs on Python threads (no numba threading
    layer, which is not safe in forked workers).
    """
    for r in range(states.shape[0]):
        run_one(states[r], observer,
                Measured(measured.bearing_rad[r], measured.bearing_sd_rad[r], measured.level_db[r]), profiles,
                errors, prior, model, settings, Outputs(out.means[r], out.covs[r], out.resampled[r], out.sds[r]))
