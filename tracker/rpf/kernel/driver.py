"""The kernel's entry point: arrays for the compiled loop from the filter's inputs, one
generator per run, and the loop over a block of runs (`tracker.rpf.batch.run_batch` calls
`run` once per block)."""

from __future__ import annotations

import numpy as np

from tracker.rpf.kernel.depthparams import DepthModel, depth_table, no_depth
from tracker.rpf.kernel.loop import run_runs
from tracker.rpf.kernel.params import Measured, Observer, Outputs, Settings, model_of, prior_of, profile_arrays
from tracker.rpf.kernel.random import seed_states


def run(*, t_s, obs_state, bearing_rad_meas, level_db_meas, k_profiles, cfg, rng, ross: bool,
        p0_db: float, sigma_l_db: float, bandwidth: float, summaries: bool, target_k=None,
        cycle_bearing_deg=None, depth=None, smoothing=None):
    """All runs, all cycles (`tracker.rpf.batch.run_batch` for one block); ``rng`` seeds one
    generator per run.

    Parameters as `run_batch`; ``ross``, ``p0_db`` and ``sigma_l_db`` are its source level
    model resolved, ``bandwidth`` the kernel's h (eqs. 27-28). ``level_db_meas`` is (runs, K)
    for one band, (runs, K, B) for several (then ``k_profiles`` holds one per-cycle sequence
    per band, and ``target_k`` one table per band). With ``depth`` (a
    `tracker.rpf.depthbatch.DepthConfig`) the depth is a state: K from ``target_k`` at the
    radials of ``cycle_bearing_deg``, averaged over ``smoothing`` (`tracker.kstructure`) when
    given.

    Returns
    -------
    means (runs, K, D), covs (runs, K, D, D), resampled (runs, K) bool, sds (runs, K, 3); with
    the depth a state it is the last of the D components.
    """
    # fresh C-ordered writable copies: a read-only or strided input would be another type
    # signature, i.e. another compile
    bearing = np.array(bearing_rad_meas, dtype=float, order="C")
    runs, n_cycles = bearing.shape
    use_level = level_db_meas is not None
    if use_level:
        level = np.array(level_db_meas, dtype=float, order="C")
        if level.ndim == 2:
            level = level[..., None]
    else:
        level = np.zeros((runs, 1, 1))
    n_bands = level.shape[2]
    d = int(cfg.n_dim) + (1 if depth is not None else 0)
    settings = Settings(n=int(cfg.n_particles), d=d, n_thr=float(cfg.neff_fraction * cfg.n_particles),
                        bandwidth=float(bandwidth), shrink=bool(cfg.shrink), summaries=bool(summaries))
    out = Outputs(means=np.empty((runs, n_cycles, d)), covs=np.empty((runs, n_cycles, d, d)),
                  resampled=np.zeros((runs, n_cycles), dtype=np.uint8),
                  sds=np.full((runs, n_cycles if summaries else 1, 3), np.nan))
    if depth is not None:
        table = depth_table(target_k, cycle_bearing_deg, n_cycles, smoothing=smoothing)
        model = DepthModel(on=True, lo_m=float(depth.depth_min_m), hi_m=float(depth.depth_max_m),
                           walk_m_per_sqrt_s=float(depth.walk_m_per_sqrt_s))
        profiles = profile_arrays(None, n_cycles, n_bands)
    else:
        table, model = no_depth(n_cycles)
        profiles = profile_arrays(k_profiles if use_level else None, n_cycles, n_bands)
    states = seed_states(rng, runs)
    run_runs(states,
             Observer(t_s=np.array(t_s, dtype=float, order="C"),
                      state=np.array(obs_state, dtype=float, order="C")),
             Measured(bearing_rad=bearing, level_db=level), profiles, table, model,
             prior_of(cfg),
             model_of(cfg, use_level=use_level, ross=ross, p0_db=p0_db, sigma_l_db=sigma_l_db),
             settings, out)
    return out.means, out.covs, out.resampled.astype(bool), out.sds
