"""The filters' level model: K(r) at one receiver depth as the particle filters read it (W = SL + K(r)).

Every face gives it (``Tables.level_profile``, and where the observer is ``level_profiles_at``);
the compiled particle-filter kernel reads the same rule from its arrays
(``tracker.rpf.kernel.likelihood``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from acoustics.levelrange import BEYOND_GRID_PENALTY_DB


@dataclass(frozen=True, slots=True, kw_only=True)
class LevelProfile:
    """K(r) at one receiver depth as the particle filters' level model uses it (W = SL + K(r)).

    Linear in range inside the axis, the first value below it, and beyond the last range the
    last value less `BEYOND_GRID_PENALTY_DB`: the grid's range axis is the horizon of the level
    model, and a particle beyond it keeps a weight only if every particle is beyond it. (Holding
    the end value lets a fast, receding target far outside the grid explain a steady level as
    well as the true one.) Ranges where the grid has no K (beyond land) get the smallest K less
    the same penalty.
    """

    range_m: np.ndarray
    k_db: np.ndarray
    #: sd of the K error along the same ranges, dB, where the grid carries a measured one
    #: (``k_error_sd_db``); None: the filters' sigma_l alone.
    k_sd_db: np.ndarray | None = None

    def sd_at(self, range_m) -> np.ndarray:
        """The K error sd at ranges, dB (linear, end values held); 0 without one."""
        r = np.asarray(range_m, dtype=float)
        if self.k_sd_db is None:
            return np.zeros(r.shape)
        return np.interp(r, self.range_m, self.k_sd_db)

    def __post_init__(self) -> None:
        k = np.asarray(self.k_db, dtype=float)
        if not np.all(np.isfinite(k)):
            finite = k[np.isfinite(k)]
            floor = (finite.min() if finite.size else 0.0) - BEYOND_GRID_PENALTY_DB
            object.__setattr__(self, "k_db", np.where(np.isfinite(k), k, floor))

    def __call__(self, range_m) -> np.ndarray:
        """K at the given ranges, dB."""
        r = np.asarray(range_m, dtype=float)
        k = np.interp(r, self.range_m, self.k_db)
        return np.where(r > self.range_m[-1], k - BEYOND_GRID_PENALTY_DB, k)


__all__ = ["LevelProfile"]
