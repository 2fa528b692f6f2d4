"""One way to track a target from a measurement file: ``track(grid, measurements, method=...)``.

It checks the measurements against the grid once (bands, class and band choices, observer depths,
bearings) and hands the estimator validated input: the maximum-likelihood motion analysis of
Grinenkov & Mashoshin (``ml``) or the regularized particle filters of Iglesis & de Montella
(``rpf`` bearings and SPL, ``rpf-bot`` bearings only, ``rpf-vp`` bearings and SPL with the
variance-preserving regularization).
"""

from __future__ import annotations

from enum import StrEnum

import numpy as np
import pandas as pd

from acoustics.grid.tables import GridTables
from envdata.errors import InputError
from tracker.errors import MeasurementFileError
from tracker.measurements import Measurements


class Method(StrEnum):
    ML = "ml"
    RPF = "rpf"
    RPF_BOT = "rpf-bot"
    RPF_VP = "rpf-vp"


def track(tables: GridTables, measurements: Measurements, *, method: Method | str = "ml",
          rng: np.random.Generator | None = None, cls_name: str | None = None,
          band: str | None = None, ml_params=None, rpf_config=None) -> pd.DataFrame:
    """Track one target; one row per cycle per class hypothesis (docs/formats.md "Track CSV").

    Parameters
    ----------
    tables : GridTables
        The propagation grid (``acoustics.open_grid``, or ``acoustics.as_tables`` of a dataset).
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
    if not np.isfinite(m.bearing_deg).any():
        raise MeasurementFileError(f"{m.source}: column bearing_deg: no bearing in any row")
    if method is Method.ML:
        from tracker import mltma

        return mltma.track_measurements(tables, m, cls_name=cls_name, band=band, params=ml_params)
    from tracker import rpf

    if rng is None:
        raise InputError(f"method {method}: the particle filters need a random generator (rng)")
    return rpf.track_measurements(tables, m, method=method.value, rng=rng, cls_name=cls_name,
                                  band=band, config=rpf_config)
