"""The ML tracker for a track: one cycle at a time (MLTracker) or a whole measurement file."""

from __future__ import annotations

import logging
import math

import numpy as np
import pandas as pd

from acoustics.grid.face import Tables
from tracker.errors import MeasurementFileError
from tracker.measurements import Measurements
from tracker.mltma.batch import MLBatch
from tracker.mltma.params import MLParams
from tracker.trackfile import TRACK_COLUMNS

log = logging.getLogger(__name__)


class MLTracker:
    """One-cycle-at-a-time API: all class hypotheses of a grid (or the chosen ones) in parallel.

    Examples
    --------
    >>> trk = MLTracker(grid, capacity=len(m))          # doctest: +SKIP
    >>> for i in range(len(m)):
    ...     rows = trk.update_from(m, i)                # one DataFrame row per class
    """

    def __init__(self, tables: Tables, *, capacity: int, class_names=None,
                 params: MLParams | None = None):
        chosen = tables.class_names if class_names is None else tuple(class_names)
        self.class_names = tuple(chosen)                      # one batch row per class
        self.grid_bands = list(tables.band_names)             # band order of the level arrays
        self.batch = MLBatch(tables, [tables.class_index(c) for c in chosen], capacity, params)
        self._skipped = 0                                     # cycles without a bearing so far
        self._last_obs = None   # (t_s, obs_x_m, obs_y_m) of the last cycle: observer velocity

    def update(self, *, t_s, obs_x_m, obs_y_m, bearing_deg, bearing_sigma_deg=math.nan,
               levels_db: dict | None = None, snrs_db: dict | None = None,
               obs_velocity_mps: tuple[float, float] | None = None,
               obs_depth_m: float | None = None) -> pd.DataFrame | None:
        """Process one cycle; returns the track rows (one per class) or None for a NaN bearing.

        K(r) is taken at ``obs_depth_m`` (default the grid's observer depth).
        """
        if not math.isfinite(bearing_deg):
            if self._skipped == 0:
                log.warning("cycle at t = %g s has no bearing; such cycles are skipped", t_s)
            self._skipped += 1
            return None
        m = len(self.grid_bands)
        lv = np.full(m, np.nan)
        sn = np.full(m, np.nan)
        for name, val in (levels_db or {}).items():
            lv[self.grid_bands.index(name)] = val
        for name, val in (snrs_db or {}).items():
            sn[self.grid_bands.index(name)] = val
        if obs_velocity_mps is None:
            if self._last_obs is None:
                obs_velocity_mps = (0.0, 0.0)
            else:
                pt, px, py = self._last_obs
                obs_velocity_mps = ((obs_x_m - px) / (t_s - pt), (obs_y_m - py) / (t_s - pt))
        self._last_obs = (t_s, obs_x_m, obs_y_m)
        out = self.batch.update(t_s, obs_x_m, obs_y_m, obs_velocity_mps[0], obs_velocity_mps[1],
                                bearing_deg, bearing_sigma_deg, lv[None, :], sn[None, :],
                                obs_depth_m=obs_depth_m)
        return _frame(t_s, self.class_names, out)

    def update_from(self, m: Measurements, i: int, obs_vel=None) -> pd.DataFrame | None:
        """Process row i of a Measurements object."""
        if obs_vel is None:
            obs_vel = (None if i == 0 else
                       ((m.obs_x_m[i] - m.obs_x_m[i - 1]) / (m.t_s[i] - m.t_s[i - 1]),
                        (m.obs_y_m[i] - m.obs_y_m[i - 1]) / (m.t_s[i] - m.t_s[i - 1])))
        return self.update(t_s=float(m.t_s[i]), obs_x_m=float(m.obs_x_m[i]),
                           obs_y_m=float(m.obs_y_m[i]), bearing_deg=float(m.bearing_deg[i]),
                           bearing_sigma_deg=float(m.bearing_sigma_deg[i]),
                           levels_db=dict(zip(m.band_names, m.level_db[i])),
                           snrs_db=dict(zip(m.band_names, m.snr_db[i])), obs_velocity_mps=obs_vel,
                           obs_depth_m=float(m.obs_depth_m[i]))


def _frame(t_s, class_names, out) -> pd.DataFrame:
    return pd.DataFrame({"t_s": t_s, "class": list(class_names), "x_m": out["x_m"],
                         "y_m": out["y_m"], "range_m": out["range_m"],
                         "bearing_deg": out["bearing_deg"], "course_deg": out["course_deg"],
                         "speed_mps": out["speed_mps"], "range_sd_m": out["range_sd_m"],
                         "course_sd_deg": out["course_sd_deg"],
                         "speed_sd_mps": out["speed_sd_mps"], "tack": out["tack"],
                         "method": "ml", "depth_m": np.nan,
                         "depth_sd_m": np.nan}).loc[:, list(TRACK_COLUMNS)]


def track_measurements(tables: Tables, measurements: Measurements, *,
                       cls_name: str | None = None, band: str | None = None,
                       params: MLParams | None = None) -> pd.DataFrame:
    """Run the ML tracker over a whole measurement file; one row per cycle per class.

    The measurements are checked against the grid by ``tracker.track.track``, the way in.

    Parameters
    ----------
    tables : Tables
    measurements : Measurements
        Cycles with a NaN bearing are skipped (said once).
    cls_name : str, optional
        Only this class hypothesis (default: every class of the grid).
    band : str, optional
        Use only this band's levels.
    """
    if band is not None and band not in measurements.band_names:
        raise MeasurementFileError(f"{measurements.source}: band {band!r}: no level_db_{band} "
                                   f"column (bands: {', '.join(measurements.band_names)})")
    m = measurements
    if band is not None:
        j = m.band_names.index(band)
        m = Measurements(source=m.source, t_s=m.t_s, obs_x_m=m.obs_x_m, obs_y_m=m.obs_y_m,
                         obs_depth_m=m.obs_depth_m, bearing_deg=m.bearing_deg,
                         bearing_sigma_deg=m.bearing_sigma_deg, band_names=(band,),
                         level_db=m.level_db[:, j:j + 1], snr_db=m.snr_db[:, j:j + 1])
    good = np.flatnonzero(np.isfinite(m.bearing_deg))
    if len(good) < len(m):
        log.warning("%s: %d cycle(s) without a bearing skipped (first at t = %g s)", m.source,
                    len(m) - len(good), m.t_s[np.flatnonzero(~np.isfinite(m.bearing_deg))[0]])
    m = m.take(good)
    vx, vy = m.obs_velocity_mps()
    trk = MLTracker(tables, capacity=len(m), class_names=None if cls_name is None else [cls_name],
                    params=params)
    frames = [trk.update_from(m, i, obs_vel=(vx[i], vy[i])) for i in range(len(m))]
    return pd.concat(frames, ignore_index=True)
