"""Detection range of a target class along bearings from a grid's observer (a detection map).

K(r) is taken between radials as the trackers take it (the grid's typed face), then the
detection rule of ``acoustics.detection`` is applied per bearing; beyond land K is NaN, which is
never detected. On a grid without bearings every bearing has the same range.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from acoustics.detection import DetectionTerms, detection_terms, farthest_m
from acoustics.grid.face import Tables


@dataclass(frozen=True, slots=True, kw_only=True)
class DetectionMap:
    """Detection ranges of one class at its mean level, per band and bearing.

    Attributes
    ----------
    cls_name : str
    terms : DetectionTerms
        The level, noise and sonar used.
    bearing_deg : ndarray, shape (B,)
        Bearings, deg, clockwise from true north at the origin.
    band_names : tuple of str
    band_range_m : ndarray, shape (M, B)
        Largest range at which each band is detected, m; NaN where it is nowhere.
    range_m : ndarray, shape (B,)
        Largest range at which any band is detected, m; NaN where none is.
    """

    cls_name: str
    terms: DetectionTerms
    bearing_deg: np.ndarray
    band_names: tuple[str, ...]
    band_range_m: np.ndarray
    range_m: np.ndarray


def class_terms(tables: Tables, cls_name: str) -> DetectionTerms:
    """The detection terms of a class of a grid in the grid's bands."""
    return detection_terms(tables.area, tables.classes[tables.class_index(cls_name)], tables.bands)


def class_k_db(tables: Tables, cls_name: str, bearing_deg: np.ndarray) -> np.ndarray:
    """K(r) of a class at the observer depth along bearings, (B, M, R), dB (K of a grid without
    bearings repeated on each)."""
    k = np.asarray(tables.k_db(None, bearing_deg)[tables.class_index(cls_name)])   # (M, [B,] R)
    k = np.broadcast_to(k if k.ndim == 3 else k[:, None, :],
                        (len(tables.bands), bearing_deg.size, tables.range_m.size))
    return np.moveaxis(k, 1, 0)


def detection_map(tables: Tables, cls_name: str, bearing_deg) -> DetectionMap:
    """Detection ranges of a class at its mean level along bearings from the grid's observer.

    Parameters
    ----------
    tables : Tables
        A grid (``acoustics.open_tables``).
    cls_name : str
        A class of the grid.
    bearing_deg : array_like, shape (B,)
        Bearings to evaluate, deg.
    """
    terms = class_terms(tables, cls_name)
    bearings = np.atleast_1d(np.asarray(bearing_deg, dtype=float))
    det = terms.detected(class_k_db(tables, cls_name, bearings))                # (B, M, R)
    rng = tables.range_m
    return DetectionMap(cls_name=cls_name, terms=terms, bearing_deg=bearings,
                        band_names=tables.band_names,
                        band_range_m=farthest_m(rng, det).T, range_m=farthest_m(rng, det.any(axis=1)))
