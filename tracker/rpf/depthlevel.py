"""The level likelihood with the target's depth a state, numpy reference: K at each particle's
depth, range and the cycle's bearing, by the compiled kernel's rule.

K comes from the (depth, range) slabs of each band's `acoustics.grid.targetdepth.TargetDepthK`
(one per radial, one on a flat grid): bilinear in depth and range, the ends of both axes held,
linear between the two radials around the cycle's measured bearing (NaN: the last bearing
before it), the cells without water at the trackers' penalty (`TargetDepthK.level_table`) and
beyond the range axis the penalty taken off (`acoustics.levelrange.BEYOND_GRID_PENALTY_DB`).
With a `tracker.kstructure.RangeSmoothing`, K is averaged over that range uncertainty and its
spread there is the sd of K's error: the level's variance is sigma_l^2 + sd^2 (the density's
-1/2 ln of it left out, as `tracker.rpf.likelihood.level_loglik` says why).

`level_arrays` and `cycle_bearings_deg` build the same tables for the compiled loop
(`tracker.rpf.kernel.depthparams.depth_table`).
"""

from __future__ import annotations

import math

import numpy as np

from acoustics.levelrange import BEYOND_GRID_PENALTY_DB
from envdata.classes import SourceLevelModel, ross_source_level_db


def cycle_bearings_deg(bearing_deg, n_cycles: int) -> np.ndarray:
    """The bearing whose radials each cycle reads, deg: the cycle's, else the last measured
    before it; before any, the first one (all 0 without any)."""
    b = np.asarray(bearing_deg, dtype=float)
    known = np.isfinite(b)
    if not known.any():
        return np.zeros(n_cycles)
    idx = np.where(known, np.arange(b.size), 0)
    np.maximum.accumulate(idx, out=idx)
    fill = b[idx]
    fill[~np.isfinite(fill)] = b[known][0]
    return fill[:n_cycles]


def level_arrays(target_k, smoothing=None) -> tuple[np.ndarray, np.ndarray | None]:
    """K of each band (B, J, Z, R), dB, the cells without water at the penalty, and the sd of
    its error there (same shape) when ``smoothing`` averages it over a range uncertainty (else
    None). ``target_k``: one `TargetDepthK` or a sequence, one per band."""
    bands = list(target_k) if isinstance(target_k, (list, tuple)) else [target_k]
    k_db = np.stack([tk.level_table() for tk in bands])
    if smoothing is None or smoothing.off:
        return np.ascontiguousarray(k_db), None
    from tracker.kstructure import smoothed_k

    mean, var = smoothed_k(np.stack([np.asarray(tk.k_db, dtype=float) for tk in bands]),
                           bands[0].range_m, smoothing)
    return (np.ascontiguousarray(np.where(np.isfinite(mean), mean, k_db)),
            np.ascontiguousarray(np.sqrt(np.where(np.isfinite(var), var, 0.0))))


class DepthLevels:
    """The level model of `tracker.rpf.batch.run_batch`'s numpy engine with the depth a state."""

    def __init__(self, target_k, cycle_bearing_deg, n_cycles: int, *, smoothing=None):
        first = (list(target_k) if isinstance(target_k, (list, tuple)) else [target_k])[0]
        self.depth_m = np.asarray(first.depth_m, dtype=float)
        self.range_m = np.asarray(first.range_m, dtype=float)
        self.k_db, self.sd_db = level_arrays(target_k, smoothing)
        self.j0, self.j1, self.w1 = first.cells(cycle_bearings_deg(cycle_bearing_deg, n_cycles))

    def k_at(self, band: int, cycle: int, depth_m, range_m, table=None) -> np.ndarray:
        """K (or, with ``table``, that table's value) at depths and ranges, dB, by the kernel's rule."""
        t = self.k_db if table is None else table
        z, r = np.asarray(depth_m, dtype=float), np.asarray(range_m, dtype=float)
        jz, fz = _cells(self.depth_m, z)
        jr, fr = _cells(self.range_m, r)
        j0, j1, w1 = int(self.j0[cycle]), int(self.j1[cycle]), float(self.w1[cycle])
        k = _bilinear(t[band, j0], jz, fz, jr, fr)
        if w1 > 0.0:
            k = k + w1 * (_bilinear(t[band, j1], jz, fz, jr, fr) - k)
        if table is None:
            k = np.where(r > self.range_m[-1], k - BEYOND_GRID_PENALTY_DB, k)
        return k

    def loglik(self, state, level_db, obs_vel_mps, band: int, cycle: int, sigma_db: float, *,
               source_level_model=SourceLevelModel.ROSS, p0_db: float = math.nan) -> np.ndarray:
        """Log of eq. 33 up to a constant for particles ``state`` (D, ...), the depth last and a
        source-level offset in component 4 when D = 6."""
        r = np.hypot(state[0], state[1])
        z = state[-1]
        if SourceLevelModel(source_level_model) is SourceLevelModel.ROSS:
            sl = ross_source_level_db(np.hypot(state[2] + float(obs_vel_mps[0]), state[3] + float(obs_vel_mps[1])))
        else:
            sl = np.full(r.shape, p0_db)
        pred = sl + self.k_at(band, cycle, z, r)
        if state.shape[0] > 5:
            pred = pred + state[4]
        d = level_db - pred
        if self.sd_db is None:
            return -0.5 * (d / sigma_db) ** 2
        sd = self.k_at(band, cycle, z, r, table=self.sd_db)
        return -0.5 * d * d / (sigma_db ** 2 + sd * sd)


def _cells(axis: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Cell and weight of ``v`` on an increasing axis, the ends held (the kernel's `axis_cell`)."""
    m = axis.size
    if m < 2:
        return np.zeros(v.shape, dtype=np.int64), np.zeros(v.shape)
    j = np.clip(np.searchsorted(axis, v, side="right") - 1, 0, m - 2)
    f = np.clip((v - axis[j]) / (axis[j + 1] - axis[j]), 0.0, 1.0)
    return j, f


def _bilinear(slab: np.ndarray, jz, fz, jr, fr) -> np.ndarray:
    """The kernel's `slab_k`."""
    jz1 = np.minimum(jz + 1, slab.shape[0] - 1)
    jr1 = np.minimum(jr + 1, slab.shape[1] - 1)
    low = slab[jz, jr] + fr * (slab[jz, jr1] - slab[jz, jr])
    high = slab[jz1, jr] + fr * (slab[jz1, jr1] - slab[jz1, jr])
    return low + fz * (high - low)
