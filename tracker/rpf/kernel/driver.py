"""The kernel's entry point: arrays for the compiled loop from the filter's inputs, one
generator per run, and the loop over a block of runs (`tracker.rpf.batch.run_batch` calls
`run` once per block)."""

from __future__ import annotations

import numpy as np

from tracker.rpf.kernel.loop import run_runs
from tracker.rpf.kernel.params import (
    Measured,
    Observer,
    Outputs,
    Settings,
    errors_of,
    model_of,
    prior_of,
    profile_arrays,
)
from tracker.rpf.kernel.random import seed_states


def run(*, t_s, obs_state, bearing_rad_meas, level_db_meas, k_profiles, cfg, rng, ross: bool,
        p0_db: float, sigma_l_db: float, bandwidth: float, summaries: bool, level_errors=None,
        displacement_m=None, bearing_sd_rad=None):
    """All runs, all cycles (`tracker.rpf.batch.run_batch` for one block); ``rng`` seeds one
    generator per run.

    Parameters as `run_batch`; ``ross``, ``p0_db`` and ``sigma_l_db`` are its source level
    model resolved, ``bandwidth`` the kernel's h (eqs. 27-28). ``level_db_meas`` is (runs, K)
    for one band, (runs, K, B) for several (then ``k_profiles`` holds one per-cycle sequence
    per band). ``level_errors`` (`tracker.levels.LevelErrors`) are integrated out per particle,
    their sds grown with the observer's ``displacement_m`` (K,) from the tables' origin.
    ``bearing_sd_rad`` (runs, K): each bearing's sd (NaN, or None: the filter's sigma_theta).

    Returns
    -------
    means (runs, K, D), covs (runs, K, D, D), resampled (runs, K) bool, sds (runs, K, 3).
    """
    # fresh C-ordered writable copies: a read-only or strided input would be another type
    # signature, i.e. another compile
    bearing = np.array(bearing_rad_meas, dtype=float, order="C")
    runs, n_cycles = bearing.shape
    bearing_sd = np.full((runs, n_cycles), np.radians(cfg.bearing_sigma_deg))
    if bearing_sd_rad is not None:
        given = np.broadcast_to(np.asarray(bearing_sd_rad, dtype=float), (runs, n_cycles))
        bearing_sd = np.where(np.isfinite(given) & (given > 0), given, bearing_sd)
    use_level = level_db_meas is not None
    if use_level:
        level = np.array(level_db_meas, dtype=float, order="C")
        if level.ndim == 2:
            level = level[..., None]
    else:
        level = np.zeros((runs, 1, 1))
    n_bands = level.shape[2]
    d = int(cfg.n_dim)
    settings = Settings(n=int(cfg.n_particles), d=d, n_thr=float(cfg.neff_fraction * cfg.n_particles),
                        bandwidth=float(bandwidth), shrink=bool(cfg.shrink), summaries=bool(summaries))
    out = Outputs(means=np.empty((runs, n_cycles, d)), covs=np.empty((runs, n_cycles, d, d)),
                  resampled=np.zeros((runs, n_cycles), dtype=np.uint8),
                  sds=np.full((runs, n_cycles if summaries else 1, 3), np.nan))
    profiles = profile_arrays(k_profiles if use_level else None, n_cycles, n_bands)
    errors = errors_of(level_errors if use_level else None, n_bands, n_cycles, displacement_m)
    states = seed_states(rng, runs)
    run_runs(states,
             Observer(t_s=np.array(t_s, dtype=float, order="C"),
                      state=np.array(obs_state, dtype=float, order="C")),
             Measured(bearing_rad=bearing, bearing_sd_rad=np.ascontiguousarray(bearing_sd), level_db=level),
             profiles, errors,
             prior_of(cfg),
             model_of(cfg, use_level=use_level, ross=ross, p0_db=p0_db, sigma_l_db=sigma_l_db),
             settings, out)
    return out.means, out.covs, out.resampled.astype(bool), out.sds
