"""The particle filter with the target's depth as a state: `DepthConfig` and `run_batch_depth`.

Not in Iglesis & de Montella (who name the unknown source parameters as their future work):
a class's tables are computed at one depth, and a target elsewhere in the water column gives
levels the class's K(r) cannot explain. Here each particle carries a depth, prior uniform over
the class's ``depth_range_m`` (or the water the tables hold), moving by a slow random walk, and
the level likelihood (eq. 33) takes K at the particle's depth, range and the cycle's bearing
from the tables' depth axis (`acoustics.grid.targetdepth.TargetDepthK`): the practice of
particle filters that carry environmental or source parameters against precomputed fields
(Yardim, Gerstoft & Hodgkiss, JASA 127, 2010). The depth is a case of `tracker.rpf.batch.run_batch`
(its ``depth`` argument): the one compiled loop (`tracker.rpf.kernel.loop`) and the numpy
reference engine both carry it. The levels may be those of several bands at once.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from envdata.classes import SourceLevelModel
from tracker.rpf.batch import BatchResult, run_batch
from tracker.rpf.config import RpfConfig

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
                    threads: int = 1, smoothing=None) -> BatchResult:
    """Run the RPF with a depth state over K cycles for a batch of runs sharing one observer.

    Parameters as `tracker.rpf.batch.run_batch`, with in place of ``k_profiles``:

    target_k : acoustics.grid.targetdepth.TargetDepthK, or a sequence of B of them
        K against target depth and range of the class and band (``tables.target_depth_k``);
        one per band when ``level_db_meas`` is (runs, K, B).
    cycle_bearing_deg : ndarray, shape (K,)
        Bearing whose radials each cycle reads, deg (the measured one; NaN: the last before).
    depth : DepthConfig
    smoothing : tracker.kstructure.RangeSmoothing, optional
        K averaged over that range uncertainty, its spread added to the level's variance.

    Returns
    -------
    BatchResult
        ``mean`` (runs, K, D) and ``cov`` with D = 5 (6 with the source-level offset), the
        target's depth last, m.
    """
    return run_batch(t_s=t_s, obs_state=obs_state, bearing_rad_meas=bearing_rad_meas,
                     level_db_meas=level_db_meas, k_profiles=None, cfg=cfg, rng=rng,
                     source_level_model=source_level_model, p0_db=p0_db, p0_sd_db=p0_sd_db,
                     summaries=summaries, threads=threads, target_k=target_k,
                     cycle_bearing_deg=cycle_bearing_deg, depth=depth, smoothing=smoothing)
