"""tmakit's measurement CSV as Stone Soup detections, and a Stone Soup track as tmakit's track CSV.

Each cycle of a measurement file (``tracker.measurements``) becomes one ``Detection`` at
``epoch + t_s`` whose measurement model is a `TablesMeasurementModel` for that cycle: the
observer where it was (through an atlas, the tables around that position:
``Tables.at_observer``), the bands whose level the cycle holds. Its metadata carries the
observer and the cycle's time, so Stone Soup's metrics and plotters see where the sensor was.
A cycle without a bearing gives no detection. A Stone Soup track (states (x, vx, y, vy) with
covariances, particle states included) becomes the rows of a track CSV (docs/formats.md "Track
CSV"), so that ``tmakit track --plot`` and the studies read it as any tracker's; and a track
CSV's class becomes a Stone Soup ``Track`` of Gaussian states, for Stone Soup's metrics.
"""

from __future__ import annotations

import datetime as dt
import math

import numpy as np
import pandas as pd
from stonesoup.types.detection import Detection
from stonesoup.types.state import GaussianState, StateVector
from stonesoup.types.track import Track

from tracker.measurements import Measurements
from tracker.stonesoup.model import VX, VY, TablesMeasurementModel, X, Y
from tracker.trackfile import check_track

#: The epoch of the detections' timestamps: cycle t_s seconds after it.
EPOCH = dt.datetime(2000, 1, 1)


def timestamp(t_s: float, epoch: dt.datetime = EPOCH) -> dt.datetime:
    return epoch + dt.timedelta(seconds=float(t_s))


def detections_from_measurements(m: Measurements, tables, cls_name: str, *, bearing_sd_deg: float,
                                 level_sd_db: float, epoch: dt.datetime = EPOCH
                                 ) -> list[tuple[dt.datetime, set[Detection]]]:
    """Per cycle, its time and its detections (one, or none without a bearing).

    Parameters
    ----------
    m : Measurements
    tables : Tables
        The grid or atlas face (``acoustics.open_tables``).
    cls_name : str
        The class hypothesis.
    bearing_sd_deg : float
        Bearing error sd, deg, where the file gives none (``bearing_sigma_deg``).
    level_sd_db : float
        The level measurement's error sd, dB (the model adds the class's source-level sd and
        the K error sd).
    """
    ic = tables.class_index(cls_name)
    band_of = [tables.band_index(name) for name in m.band_names]
    out = []
    for k in range(len(m)):
        when = timestamp(m.t_s[k], epoch)
        if not np.isfinite(m.bearing_deg[k]):
            out.append((when, set()))
            continue
        present = [j for j in range(len(m.band_names)) if np.isfinite(m.level_db[k, j])]
        sd = m.bearing_sigma_deg[k] if np.isfinite(m.bearing_sigma_deg[k]) else bearing_sd_deg
        x, y, depth = float(m.obs_x_m[k]), float(m.obs_y_m[k]), float(m.obs_depth_m[k])
        model = TablesMeasurementModel(
            tables=tables.at_observer(x, y), class_index=ic, band_index=tuple(band_of[j] for j in present),
            observer_x_m=x, observer_y_m=y, observer_depth_m=depth, bearing_sd_rad=math.radians(sd),
            level_sd_db=level_sd_db)
        z = StateVector([math.radians(m.bearing_deg[k])] + [float(m.level_db[k, j]) for j in present])
        meta = {"t_s": float(m.t_s[k]), "obs_x_m": x, "obs_y_m": y, "obs_depth_m": depth,
                "bands": [m.band_names[j] for j in present]}
        out.append((when, {Detection(z, timestamp=when, measurement_model=model, metadata=meta)}))
    return out


def observer_lookup(m: Measurements, epoch: dt.datetime = EPOCH):
    """timestamp -> (x_m, y_m, depth_m) of the observer at that cycle (the latest cycle not after it)."""
    t = np.asarray(m.t_s, dtype=float)

    def at(when: dt.datetime) -> tuple[float, float, float]:
        k = int(np.clip(np.searchsorted(t, (when - epoch).total_seconds(), side="right") - 1, 0, t.size - 1))
        return float(m.obs_x_m[k]), float(m.obs_y_m[k]), float(m.obs_depth_m[k])
    return at


def track_frame(states, m: Measurements, cls_name: str, *, method: str = "stonesoup",
                epoch: dt.datetime = EPOCH) -> pd.DataFrame:
    """tmakit's track table from Stone Soup states (x, vx, y, vy), one per cycle of ``m``: the
    mean and its covariance (a particle state's weighted ones), range and bearing from the
    observer of the cycle, course and speed with their sds (first order)."""
    rows = []
    for state in states:
        t_s = (state.timestamp - epoch).total_seconds()
        k = int(np.argmin(np.abs(np.asarray(m.t_s) - t_s)))
        mean = np.asarray(state.mean, dtype=float).ravel()
        cov = np.asarray(state.covar, dtype=float)
        x, y, vx, vy = mean[X], mean[Y], mean[VX], mean[VY]
        dx, dy = x - m.obs_x_m[k], y - m.obs_y_m[k]
        rng = math.hypot(dx, dy)
        speed = math.hypot(vx, vy)
        # first-order sds: range along the line of sight, speed along the velocity, course across it
        u = np.array([dx, 0.0, dy, 0.0]) / max(rng, 1e-9)
        v = np.array([0.0, vx, 0.0, vy]) / max(speed, 1e-9)
        w = np.array([0.0, vy, 0.0, -vx]) / max(speed, 1e-9) ** 2
        rows.append({"t_s": float(m.t_s[k]), "class": cls_name, "x_m": x, "y_m": y, "range_m": rng,
                     "bearing_deg": math.degrees(math.atan2(dx, dy)) % 360.0,
                     "course_deg": math.degrees(math.atan2(vx, vy)) % 360.0, "speed_mps": speed,
                     "range_sd_m": math.sqrt(max(u @ cov @ u, 0.0)),
                     "course_sd_deg": math.degrees(math.sqrt(max(w @ cov @ w, 0.0))),
                     "speed_sd_mps": math.sqrt(max(v @ cov @ v, 0.0)), "tack": 1, "method": method,
                     "depth_m": np.nan, "depth_sd_m": np.nan})
    return check_track(pd.DataFrame(rows), where="stonesoup track")


def track_from_frame(df: pd.DataFrame, cls_name: str | None = None, *, epoch: dt.datetime = EPOCH) -> Track:
    """One class's rows of a track table (``tracker.trackfile.read_track``) as a Stone Soup track:
    Gaussian states (x, vx, y, vy) at ``epoch + t_s``, the covariance from the row's range, course
    and speed sds (first order, along the line of sight of a track with no observer: the
    position's sd is the range sd in both axes; the velocity's from course and speed)."""
    rows = df if cls_name is None else df[df["class"] == cls_name]
    if rows.empty:
        raise ValueError(f"track has no rows{'' if cls_name is None else f' of class {cls_name!r}'}")
    states = []
    for r in rows.itertuples(index=False):
        course = math.radians(r.course_deg)
        vx, vy = r.speed_mps * math.sin(course), r.speed_mps * math.cos(course)
        # velocity covariance: speed sd along the course, speed x course sd across it
        along = np.array([math.sin(course), math.cos(course)])
        across = np.array([math.cos(course), -math.sin(course)])
        cv = (r.speed_sd_mps ** 2 * np.outer(along, along)
              + (r.speed_mps * math.radians(r.course_sd_deg)) ** 2 * np.outer(across, across))
        cov = np.zeros((4, 4))
        cov[X, X] = cov[Y, Y] = r.range_sd_m ** 2
        cov[np.ix_([VX, VY], [VX, VY])] = cv
        states.append(GaussianState(StateVector([r.x_m, vx, r.y_m, vy]), cov, timestamp=timestamp(r.t_s, epoch)))
    return Track(states)
