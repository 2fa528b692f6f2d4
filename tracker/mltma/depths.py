"""The ML analysis with an unknown target depth: class hypotheses times depth hypotheses.

Not in Grinenkov & Mashoshin (their classes radiate from one depth each). For each depth
hypothesis the whole analysis runs on the tables with K at that depth
(``Tables.at_target_depth``): the level-based range, hence the track, depends on it. The bank
of `tracker.depth.bank` weighs the hypotheses by the depth's posterior along their tracks; each
cycle's row of a class is the track of the hypothesis of the largest weight then (rule
``weight``), with ``depth_m`` the posterior median and ``depth_sd_m`` its sd (docs/depth.md).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from acoustics.grid.face import Tables
from tracker.depth.bank import DepthChoice, depth_hypotheses_m, weigh_tracks
from tracker.measurements import Measurements
from tracker.mltma.params import MLParams


def track_depths(tables: Tables, m: Measurements, *, cls_name: str | None = None,
                 band: str | None = None, params: MLParams | None = None,
                 depths_m=None) -> tuple[pd.DataFrame, list[DepthChoice]]:
    """The ML analysis over class x depth hypotheses; one row per cycle per class.

    Each cycle's row of a class is the track of its hypothesis of the largest weight so far,
    with ``depth_m`` the posterior median and ``depth_sd_m`` the posterior sd (module docstring).

    Parameters
    ----------
    tables : Tables
        Must serve K at any target depth (``serves_target_depth``).
    m : Measurements
        Bearings and levels (cycles without a bearing dropped, as in
        ``tracker.mltma.track_measurements``).
    cls_name, band, params
        As ``tracker.mltma.track_measurements``; ``band`` limits the tracks and the depth's
        likelihood to that band's levels.
    depths_m : array_like, optional
        The depth hypotheses, m; default `depth_hypotheses_m` of each class's span
        (``Tables.target_depth_span_m``).

    Returns
    -------
    rows : DataFrame
        Track columns (``tracker.trackfile.TRACK_COLUMNS``).
    choices : list of DepthChoice
        Per class, the depth posterior after the last cycle.
    """
    from tracker.mltma.tracker import track_measurements

    names = tables.class_names if cls_name is None else (cls_name,)
    good = m.take(np.flatnonzero(np.isfinite(m.bearing_deg)))
    if band is not None:
        good = good.with_bands((band,))
    frames, choices = [], []
    for name in names:
        ic = tables.class_index(name)
        cls = tables.classes[ic]
        span = tables.target_depth_span_m(ic)
        z = (np.asarray(depths_m, dtype=float) if depths_m is not None
             else depth_hypotheses_m(span, cls.depth_m))
        span = (min(span[0], float(z.min())), max(span[1], float(z.max())))
        tracks = []
        for depth in z:
            view = tables.at_target_depth(float(depth))
            tracks.append(track_measurements(view, good, cls_name=name, band=None,
                                             params=params).reset_index(drop=True))
        rows, choice = weigh_tracks(tables, ic, good, tracks, z, span, rule="weight")
        frames.append(rows)
        choices.append(choice)
    return pd.concat(frames, ignore_index=True), choices


