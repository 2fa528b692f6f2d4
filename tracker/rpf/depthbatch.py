"""The particle filter with the target's depth as a state: `DepthConfig` and `run_batch_depth`.

Not in Iglesis & de Montella (who name the unknown source parameters as their future work):
a class's tables are computed at one depth, and a target elsewhere in the water column gives
levels the class's K(r) cannot explain. Here each particle carries a depth, prior uniform over
the class's ``depth_range_m`` (or the water the tables hold), moving by a slow random walk, and
the level likelihood (eq. 33) takes K at the particle's depth, range and the cycle's bearing
from the tables' depth axis (`acoustics.grid.targetdepth.TargetDepthK`): the practice of
particle filters that carry environmental or source parameters against precomputed fields
(Yardim, Gerstoft & Hodgkiss, JASA 127, 2010). The loop is the compiled kernel's
(`tracker.rpf.kernel.depthloop`); the numpy reference engine has no depth state.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from envdata.classes import SourceLevelModel
from tracker.rpf.batch import BatchResult
from tracker.rpf.config import BLOCK_PARTICLES, RpfConfig
from tracker.rpf.regularise import optimal_bandwidth

#: Default sd of the depth's random walk, m per square root of second: 6 m in an hour, about
#: what a submarine on patrol changes its depth by between manoeuvres; the regularization's
#: jitter adds its own spread at each resampling.
DEPTH_WALK_M_PER_SQRT_S = 0.1


@dataclass(frozen=True, slots=True, kw_only=True)
class DepthConfig:
    """The depth state.

    Attributes
    ----------
    depth_min_m, depth_max_m : float
        Span of the uniform prior and walls of the walk, m.
    walk_m_per_sqrt_s : float
        Random-walk sd, m s^-1/2 (`DEPTH_WALK_M_PER_SQRT_S`).
    """

    depth_min_m: float
    depth_max_m: float
    walk_m_per_sqrt_s: float = DEPTH_WALK_M_PER_SQRT_S

    def __post_init__(self) -> None:
        lo, hi = self.depth_min_m, self.depth_max_m
        if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 <= lo < hi):
            raise ValueError(f"depth span must satisfy 0 <= min < max, got [{lo}, {hi}] m")
        if not (math.isfinite(self.walk_m_per_sqrt_s) and self.walk_m_per_sqrt_s >= 0.0):
            raise ValueError(f"walk_m_per_sqrt_s must be >= 0, got {self.walk_m_per_sqrt_s}")


def run_batch_depth(*, t_s: np.ndarray, obs_state: np.ndarray, bearing_rad_meas: np.ndarray,
                    level_db_meas: np.ndarray, target_k, cycle_bearing_deg, depth: DepthConfig,
                    cfg: RpfConfig, rng: np.random.Generator,
                    source_level_model: SourceLevelModel | str = SourceLevelModel.ROSS,
                    p0_db: float = math.nan, p0_sd_db: float = 0.0, summaries: bool = False,
                    threads: int = 1) -> BatchResult:
    """Run the RPF with a depth state over K cycles for a batch of runs sharing one observer.

    Parameters as `tracker.rpf.batch.run_batch`, with in place of ``k_profiles``:

    target_k : acoustics.grid.targetdepth.TargetDepthK
        K against target depth and range of the class and band (``tables.target_depth_k``).
    cycle_bearing_deg : ndarray, shape (K,)
        Bearing whose radials each cycle reads, deg (the measured one; NaN: the last before).
    depth : DepthConfig

    Returns
    -------
    BatchResult
        ``mean`` (runs, K, D) and ``cov`` with D = 5 (6 with the source-level offset), the
        target's depth last, m.
    """
    from tracker.rpf.kernel.depthdriver import run_depth  # numba loads only here

    runs = bearing_rad_meas.shape[0]
    block = max(1, BLOCK_PARTICLES // cfg.n_particles)
    starts = list(range(0, runs, block))
    rngs = rng.spawn(len(starts))
    ross = SourceLevelModel(source_level_model) is SourceLevelModel.ROSS
    sigma_l = math.hypot(cfg.level_sigma_db, 0.0 if ross else p0_sd_db)
    h = optimal_bandwidth(cfg.n_particles, cfg.n_dim + 1)

    def one(i):
        rows = slice(starts[i], starts[i] + block)
        means, covs, resampled, sds = run_depth(
            t_s=t_s, obs_state=obs_state, bearing_rad_meas=bearing_rad_meas[rows],
            level_db_meas=level_db_meas[rows], target_k=target_k,
            cycle_bearing_deg=cycle_bearing_deg, depth_span_m=(depth.depth_min_m, depth.depth_max_m),
            walk_m_per_sqrt_s=depth.walk_m_per_sqrt_s, cfg=cfg, rng=rngs[i],
            ross=ross, p0_db=p0_db, sigma_l_db=sigma_l, bandwidth=h,
            summaries=summaries)
        return BatchResult(mean=means, cov=covs, resampled=resampled,
                           extra={"sd": sds} if summaries else {})

    if threads > 1 and len(starts) > 1:
        from concurrent.futures import ThreadPoolExecutor

        with ThreadPoolExecutor(max_workers=threads) as pool:
            parts = list(pool.map(one, range(len(starts))))
    else:
        parts = [one(i) for i in range(len(starts))]
    if len(parts) == 1:
        return parts[0]
    return BatchResult(mean=np.concatenate([p.mean for p in parts]),
                       cov=np.concatenate([p.cov for p in parts]),
                       resampled=np.concatenate([p.resampled for p in parts]),
                       extra={"sd": np.concatenate([p.extra["sd"] for p in parts])}
                       if summaries else {})
