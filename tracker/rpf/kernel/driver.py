"""The kernel's entry point: arrays for the compiled loop from the filter's inputs, one
generator per run, and the loop over a block of runs (`tracker.rpf.batch.run_batch` calls
`run` once per block)."""

from __future__ import annotations

import math

import numpy as np

from tracker.rpf.kernel.loop import run_runs
from tracker.rpf.kernel.random import seed_states


def profile_arrays(k_profiles, n_cycles: int):
    """Stack the distinct K(r) profiles (objects with ``range_m`` and ``k_db``) of the cycles.

    Returns
    -------
    prof_idx : ndarray of int, shape (K,)
        Row of each cycle's profile (0 where the cycle has none).
    prof_r, prof_k : ndarray, shape (P, M)
        Range axes, m, and K values, dB, padded with their last value.
    prof_len : ndarray of int, shape (P,)
        Number of points of each.
    """
    rows, where = [], {}
    prof_idx = np.zeros(n_cycles, dtype=np.int64)
    for k in range(n_cycles):
        p = None if k_profiles is None else k_profiles[k]
        if p is None:
            continue
        if id(p) not in where:
            where[id(p)] = len(rows)
            rows.append((np.asarray(p.range_m, dtype=float), np.asarray(p.k_db, dtype=float)))
        prof_idx[k] = where[id(p)]
    if not rows:
        return prof_idx, np.zeros((1, 1)), np.zeros((1, 1)), np.ones(1, dtype=np.int64)
    m = max(r.size for r, _ in rows)
    prof_r = np.empty((len(rows), m))
    prof_k = np.empty((len(rows), m))
    for i, (r, kk) in enumerate(rows):
        prof_r[i, :r.size], prof_r[i, r.size:] = r, r[-1]
        prof_k[i, :kk.size], prof_k[i, kk.size:] = kk, kk[-1]
    return prof_idx, prof_r, prof_k, np.array([r.size for r, _ in rows], dtype=np.int64)


def run(*, t_s, obs_state, bearing_rad_meas, level_db_meas, k_profiles, cfg, rng, ross: bool,
        p0_db: float, sigma_l_db: float, bandwidth: float, summaries: bool):
    """All runs, all cycles (`rpf.run_batch` for one block); ``rng`` seeds one generator per
    run.

    Returns
    -------
    means (runs, K, D), covs (runs, K, D, D), resampled (runs, K) bool, sds (runs, K, 3)
    """
    # fresh C-ordered writable copies: a read-only or strided input would be another type
    # signature, i.e. another compile
    bearing = np.array(bearing_rad_meas, dtype=float, order="C")
    runs, n_cycles = bearing.shape
    d, n = cfg.n_dim, cfg.n_particles
    use_level = level_db_meas is not None
    level = (np.array(level_db_meas, dtype=float, order="C") if use_level
             else np.zeros((runs, 1)))
    prof_idx, prof_r, prof_k, prof_len = profile_arrays(k_profiles if use_level else None,
                                                        n_cycles)
    prior = np.array([cfg.range_mean_m, cfg.range_sd_m, math.radians(cfg.bearing_sigma_deg),
                      cfg.speed_mean_mps, cfg.speed_sd_mps, math.radians(cfg.course_sd_deg)])
    states = seed_states(rng, runs)
    means = np.empty((runs, n_cycles, d))
    covs = np.empty((runs, n_cycles, d, d))
    resampled = np.zeros((runs, n_cycles), dtype=np.uint8)
    sds = np.full((runs, n_cycles if summaries else 1, 3), np.nan)
    args = (states, np.array(t_s, dtype=float, order="C"),
            np.array(obs_state, dtype=float, order="C"), bearing, level, prof_idx, prof_r,
            prof_k, prof_len, use_level, bool(ross), float(p0_db), prior, float(cfg.sigma_a_mps2),
            math.radians(cfg.bearing_sigma_deg), float(sigma_l_db), float(cfg.sl_offset_sd_db),
            n, d, float(cfg.neff_fraction * n), float(bandwidth), bool(cfg.shrink),
            bool(summaries), means, covs, resampled, sds)
    run_runs(*args)
    return means, covs, resampled.astype(bool), sds

