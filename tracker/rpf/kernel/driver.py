"""The kernel's entry point: arrays for the compiled loop from the filter's inputs, one
generator per run, and the loop over a block of runs (`tracker.rpf.batch.run_batch` calls
`run` once per block)."""

from __future__ import annotations

import numpy as np

from tracker.rpf.kernel.loop import run_runs
from tracker.rpf.kernel.params import Measured, Observer, Outputs, model_of, prior_of, profile_arrays, settings_of
from tracker.rpf.kernel.random import seed_states


def run(*, t_s, obs_state, bearing_rad_meas, level_db_meas, k_profiles, cfg, rng, ross: bool,
        p0_db: float, sigma_l_db: float, bandwidth: float, summaries: bool):
    """All runs, all cycles (`tracker.rpf.batch.run_batch` for one block); ``rng`` seeds one
    generator per run.

    Parameters as `run_batch`; ``ross``, ``p0_db`` and ``sigma_l_db`` are its source level
    model resolved, ``bandwidth`` the kernel's h (eqs. 27-28).

    Returns
    -------
    means (runs, K, D), covs (runs, K, D, D), resampled (runs, K) bool, sds (runs, K, 3)
    """
    # fresh C-ordered writable copies: a read-only or strided input would be another type
    # signature, i.e. another compile
    bearing = np.array(bearing_rad_meas, dtype=float, order="C")
    runs, n_cycles = bearing.shape
    use_level = level_db_meas is not None
    level = (np.array(level_db_meas, dtype=float, order="C") if use_level
             else np.zeros((runs, 1)))
    settings = settings_of(cfg, bandwidth=bandwidth, summaries=summaries)
    d = settings.d
    out = Outputs(means=np.empty((runs, n_cycles, d)), covs=np.empty((runs, n_cycles, d, d)),
                  resampled=np.zeros((runs, n_cycles), dtype=np.uint8),
                  sds=np.full((runs, n_cycles if summaries else 1, 3), np.nan))
    states = seed_states(rng, runs)
    run_runs(states,
             Observer(t_s=np.array(t_s, dtype=float, order="C"),
                      state=np.array(obs_state, dtype=float, order="C")),
             Measured(bearing_rad=bearing, level_db=level),
             profile_arrays(k_profiles if use_level else None, n_cycles),
             prior_of(cfg),
             model_of(cfg, use_level=use_level, ross=ross, p0_db=p0_db, sigma_l_db=sigma_l_db),
             settings, out)
    return out.means, out.covs, out.resampled.astype(bool), out.sds
