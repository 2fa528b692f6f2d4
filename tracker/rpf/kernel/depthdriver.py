"""The depth-state kernel's entry point (`tracker.rpf.depthbatch.run_batch_depth` calls `run_depth`
once per block of runs), as `tracker.rpf.kernel.driver.run` for the fixed-depth loop."""

from __future__ import annotations

import numpy as np

from tracker.rpf.kernel.depthloop import run_runs_depth
from tracker.rpf.kernel.depthparams import DepthModel, depth_table
from tracker.rpf.kernel.params import Measured, Observer, Outputs, Settings, model_of, prior_of
from tracker.rpf.kernel.random import seed_states


def run_depth(*, t_s, obs_state, bearing_rad_meas, level_db_meas, target_k, cycle_bearing_deg,
              depth_span_m, walk_m_per_sqrt_s, cfg, rng, ross: bool, p0_db: float,
              sigma_l_db: float, bandwidth: float, summaries: bool):
    """All runs, all cycles, the depth a state; ``rng`` seeds one generator per run.

    Parameters as `tracker.rpf.kernel.driver.run`, and: ``target_k`` the
    `acoustics.grid.targetdepth.TargetDepthK` of the class and band; ``cycle_bearing_deg`` (K,)
    the bearing whose radials each cycle reads; ``depth_span_m`` (lo, hi) the depth prior's span
    and the walls; ``walk_m_per_sqrt_s`` the walk's sd.

    Returns
    -------
    means (runs, K, D), covs (runs, K, D, D), resampled (runs, K) bool, sds (runs, K, 3);
    D = 5 (6 with the source-level offset), the depth last.
    """
    bearing = np.array(bearing_rad_meas, dtype=float, order="C")
    runs, n_cycles = bearing.shape
    level = np.array(level_db_meas, dtype=float, order="C")
    n = int(cfg.n_particles)
    d = int(cfg.n_dim) + 1
    settings = Settings(n=n, d=d, n_thr=float(cfg.neff_fraction * n), bandwidth=float(bandwidth),
                        shrink=bool(cfg.shrink), summaries=bool(summaries))
    out = Outputs(means=np.empty((runs, n_cycles, d)), covs=np.empty((runs, n_cycles, d, d)),
                  resampled=np.zeros((runs, n_cycles), dtype=np.uint8),
                  sds=np.full((runs, n_cycles if summaries else 1, 3), np.nan))
    states = seed_states(rng, runs)
    lo, hi = (float(v) for v in depth_span_m)
    run_runs_depth(states,
                   Observer(t_s=np.array(t_s, dtype=float, order="C"),
                            state=np.array(obs_state, dtype=float, order="C")),
                   Measured(bearing_rad=bearing, level_db=level),
                   depth_table(target_k, cycle_bearing_deg, n_cycles),
                   DepthModel(lo_m=lo, hi_m=hi, walk_m_per_sqrt_s=float(walk_m_per_sqrt_s)),
                   prior_of(cfg),
                   model_of(cfg, use_level=True, ross=ross, p0_db=p0_db, sigma_l_db=sigma_l_db),
                   settings, out)
    return out.means, out.covs, out.resampled.astype(bool), out.sds
