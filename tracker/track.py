"""One way to track a target from a measurement file: ``track(grid, measurements, method=...)``.

It checks the measurements against the grid once (bands, class and band choices, observer depths,
bearings) and hands the estimator validated input: the maximum-likelihood motion analysis of
Grinenkov & Mashoshin (``ml``) or the regularized particle filters of Iglesis & de Montella
(``rpf`` bearings and SPL, ``rpf-bot`` bearings only, ``rpf-vp`` bearings and SPL with the
variance-preserving regularization).
"""

from __future__ import annotations

import math
from enum import StrEnum

import numpy as np
import pandas as pd

from acoustics.errors import ObserverPositionError
from acoustics.grid.face import OBSERVER_DEPTH_TOLERANCE_M, Tables
from envdata.errors import InputError
from tracker.errors import MeasurementFileError
from tracker.measurements import Measurements
from tracker.methods import Method


class TargetDepth(StrEnum):
    """What the trackers take the target's depth to be, beside a depth in metres."""

    CLASS = "class"      # the class's depth_m, where its tables are computed (the default)
    UNKNOWN = "unknown"  # estimated with the motion (docs/depth.md)


def track(tables: Tables, measurements: Measurements, *, method: Method | str = "ml",
          rng: np.random.Generator | None = None, cls_name: str | None = None,
          band: str | None = None, ml_params=None, rpf_config=None,
          target_depth: TargetDepth | str | float = TargetDepth.CLASS,
          range_prior_m: tuple[float, float] | None = None) -> pd.DataFrame:
    """Track one target; one row per cycle per class hypothesis (docs/formats.md "Track CSV").

    Parameters
    ----------
    tables : Tables
        The propagation grid (``acoustics.open_tables``, or ``acoustics.open_tables`` of a dataset).
    measurements : Measurements
        Bearings and band levels (``tracker.measurements.read_measurements``).
    method : {"ml", "rpf", "rpf-bot", "rpf-vp"}
        The estimator.
    rng : numpy.random.Generator, optional
        The particle filters' generator (same seed, same track); required by them.
    cls_name : str, optional
        Only this class hypothesis (default every class of the grid).
    band : str, optional
        ``ml``: use only this band's levels; ``rpf``: the band whose level is the SPL (default
        the first grid band with a level column).
    ml_params : tracker.mltma.MLParams, optional
    rpf_config : tracker.rpf.RpfConfig, optional
    target_depth : TargetDepth or float
        ``"class"``: K with the target at its class's depth (the tables as built); a depth, m:
        K with the target there (``Tables.at_target_depth``); ``"unknown"``: the depth is
        estimated over depth hypotheses (the ML analysis once per hypothesis, the particle filters
        as a bank of one filter per hypothesis; the depth reported is the posterior from the
        levels along the tracks, its final summary per class in ``DataFrame.attrs["depth"]``).
        The rows' ``depth_m`` is the depth used or estimated, ``depth_sd_m`` its sd (blank where
        assumed).
    range_prior_m : (float, float), optional
        The particle filters' prior range, log-uniform between these two ranges, m (default 1 km
        to the tables' last range; `tracker.rpf.track.default_range_span_m`). The ML analysis
        has no prior: an error there.

    Raises
    ------
    MeasurementFileError
        A level column for a band the grid lacks, an observer depth outside the grid's depth
        axis, no bearing in any row; for ``rpf``, no level column for the band.
    GridFileError
        ``cls_name`` or ``band`` is not in the grid.
    """
    try:
        method = Method(method)
    except ValueError:
        raise InputError(f"method {method!r} is not a tracker ({', '.join(Method)})") from None
    m = measurements
    if cls_name is not None:
        tables.class_index(cls_name)
    if band is not None:
        tables.band_index(band)
    for name in m.band_names:
        if name not in tables.band_names:
            raise MeasurementFileError(f"{m.source}: column 'level_db_{name}': band {name!r} is "
                                       f"not a band of the grid ({', '.join(tables.band_names)})")
    bad = np.flatnonzero(tables.outside_depth(m.obs_depth_m))
    if bad.size:
        i = int(bad[0])
        raise MeasurementFileError(f"{m.source}: row {i + 1}, column obs_depth_m: "
                                   f"{tables.depth_problem(float(m.obs_depth_m[i]))}")
    _check_observers(tables, m)
    if not np.isfinite(m.bearing_deg).any():
        raise MeasurementFileError(f"{m.source}: column bearing_deg: no bearing in any row")
    depth = _target_depth(target_depth)
    if range_prior_m is not None:
        _check_range_prior(tables, method, range_prior_m)
    if depth is TargetDepth.UNKNOWN and tables.follows_observer:
        raise InputError(f"{tables.source}: target depth unknown: not estimated yet with tables that "
                         f"follow the observer (an atlas); give the class's depth or a depth in metres")
    if depth is not TargetDepth.CLASS:
        _check_target_depth(tables, m, method, depth)
        if depth is not TargetDepth.UNKNOWN:
            tables = tables.at_target_depth(depth)
    unknown = depth is TargetDepth.UNKNOWN
    if method is Method.ML:
        from tracker import mltma

        if unknown:
            from tracker.mltma.depths import track_depths

            df, choices = track_depths(tables, m, cls_name=cls_name, band=band, params=ml_params)
            df.attrs["depth"] = choices
            return df
        df = mltma.track_measurements(tables, m, cls_name=cls_name, band=band, params=ml_params)
        return _assumed_depth(df, tables, depth)
    from tracker import rpf

    if rng is None:
        raise InputError(f"method {method}: the particle filters need a random generator (rng)")
    df = rpf.track_measurements(tables, m, method=method.value, rng=rng, cls_name=cls_name,
                                band=band, config=rpf_config, depth_unknown=unknown, range_span_m=range_prior_m)
    return df if unknown else _assumed_depth(df, tables, depth)


def _check_range_prior(tables: Tables, method: Method, span) -> None:
    """A range prior for a particle filter: two ranges, near before far, within the tables."""
    if not method.is_particle_filter:
        raise InputError(f"method {method}: a range prior is for the particle filters (rpf, rpf-bot, "
                         f"rpf-vp); the ML analysis searches every range")
    near, far = (float(v) for v in span)
    reach = float(tables.range_m[-1])
    if not (math.isfinite(near) and math.isfinite(far) and 0 < near < far):
        raise InputError(f"range prior {near / 1000:g}-{far / 1000:g} km: give two ranges, the near "
                         f"one first, both > 0")
    if far > reach:
        raise InputError(f"range prior {near / 1000:g}-{far / 1000:g} km: the tables reach "
                         f"{reach / 1000:g} km ({tables.source})")


def _check_observers(tables: Tables, m: Measurements) -> None:
    """Every observer position served by the tables (an atlas's: inside its positions)."""
    try:
        tables.check_observers(m.obs_x_m, m.obs_y_m)
    except ObserverPositionError as exc:  # the position's index -> the file's row, from 1
        raise MeasurementFileError(f"{m.source}: row {exc.index + 1}, observer position: {exc.reason}") from None
    except InputError as exc:
        raise MeasurementFileError(f"{m.source}: {exc}") from None


def _target_depth(value) -> TargetDepth | float:
    """``value`` as a `TargetDepth` or a finite depth >= 0, m."""
    if isinstance(value, str):
        try:
            return TargetDepth(value)
        except ValueError:
            pass
        try:
            value = float(value)
        except ValueError:
            raise InputError(f"target depth: {value!r} is not a depth in metres, 'class' or "
                             f"'unknown'") from None
    value = float(value)
    if not (math.isfinite(value) and value >= 0.0):
        raise InputError(f"target depth: must be a depth >= 0 m, 'class' or 'unknown', got {value:g}")
    return value


def _check_target_depth(tables: Tables, m: Measurements, method: Method, depth) -> None:
    """The measurements and method a target depth other than the class's needs."""
    if depth is TargetDepth.UNKNOWN and method is Method.RPF_BOT:
        raise InputError("target depth unknown: bearings alone say nothing of the depth; use a "
                         "method with levels (ml, rpf, rpf-vp)")
    bad = np.flatnonzero(np.abs(np.asarray(m.obs_depth_m, dtype=float) - tables.observer_depth_m)
                         > OBSERVER_DEPTH_TOLERANCE_M)
    if bad.size:
        i = int(bad[0])
        raise MeasurementFileError(
            f"{m.source}: row {i + 1}, column obs_depth_m: {float(m.obs_depth_m[i]):g} m is not the "
            f"grid's observer depth {tables.observer_depth_m:g} m; with a target depth other than "
            f"the class's the grid's TL from the observer serves that depth only")


def _assumed_depth(df: pd.DataFrame, tables: Tables, depth) -> pd.DataFrame:
    """The rows' ``depth_m``: the depth the tables assumed (the class's, or the one given)."""
    by_class = {c.name: c.depth_m for c in tables.classes}
    df["depth_m"] = ([float(depth)] * len(df) if not isinstance(depth, TargetDepth)
                     else [by_class.get(str(c), np.nan) for c in df["class"]])
    df["depth_sd_m"] = np.nan
    return df
