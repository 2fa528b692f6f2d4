"""Two grids of one area side by side: how far apart their TL and K are, by class, band and bearing.

Two grids compare when they hold the same area (by name), classes, bands, range and depth axes
and, for bearing-dependent grids, the same origin and bearings: two models, two settings, two
months of one area. Differences are B - A in dB. Statistics are taken over the cells finite in
both grids and below the shadow cap (``tl_max_db``) in both: a cell finite in one grid and not
the other (a shadow one model fills and the other does not, a radial that ends earlier) is
counted apart, never as a difference.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from acoustics.errors import GridFileError
from acoustics.grid.face import Tables
from acoustics.grid.radialtables import RadialTables

#: A TL at or above this is a capped shadow (the grids' ``tl_max_db``, 200 dB by default) less a
#: margin: compared apart, as an empty cell.
SHADOW_TL_DB = 199.0


class GridMismatchError(GridFileError):
    """Two grids that are not of one area, or not on the same axes."""


@dataclass(frozen=True, slots=True, kw_only=True)
class DiffStats:
    """|B - A| of one class and band (and bearing, for bearing-dependent grids).

    Attributes
    ----------
    cls_name, band : str
        The class and band.
    bearing_deg : float or None
        The radial; None for a flat grid, or for the row over all bearings.
    tl_median_db, tl_p90_db : float
        Median and 90th percentile of |dTL| over the cells both grids fill, dB (NaN if none).
    k_median_db, k_p90_db : float
        The same of |dK| over the ranges where both have K, dB.
    tl_signed_median_db : float
        Median of dTL = TL_B - TL_A, dB: which grid is the lossier.
    tl_cells : int
        Cells compared.
    tl_one_sided : int
        Cells one grid fills (finite, below the shadow cap) and the other does not.
    """

    cls_name: str
    band: str
    bearing_deg: float | None
    tl_median_db: float
    tl_p90_db: float
    k_median_db: float
    k_p90_db: float
    tl_signed_median_db: float
    tl_cells: int
    tl_one_sided: int


@dataclass(frozen=True, slots=True, kw_only=True)
class GridComparison:
    """The two grids' differences.

    Attributes
    ----------
    source_a, source_b : str
        The grids' names in messages (their files).
    model_a, model_b : str
        Their propagation models.
    area : str
        The area both hold.
    rows : tuple of DiffStats
        By class and band; for bearing-dependent grids first every bearing, then each class and
        band over all bearings (``bearing_deg`` None).
    range_m : ndarray, shape (R,)
        The range axis, m.
    axis_name : str
        What the picture's second axis is: ``"depth"`` (m; dTL at every depth of a flat grid) or
        ``"bearing"`` (deg; dK along every radial of a bearing-dependent grid).
    axis_values : ndarray, shape (Y,)
        That axis.
    field_db : ndarray, shape (C, M, Y, R)
        The difference field B - A of the picture, dB: dTL(depth, range) or dK(bearing, range);
        NaN where it is not compared.
    class_names, band_names : tuple of str
        The classes and bands, in grid order.
    """

    source_a: str
    source_b: str
    model_a: str
    model_b: str
    area: str
    rows: tuple[DiffStats, ...]
    range_m: np.ndarray
    axis_name: str
    axis_values: np.ndarray
    field_db: np.ndarray
    class_names: tuple[str, ...]
    band_names: tuple[str, ...]

    def to_dict(self) -> dict:
        """The comparison's figures as JSON-able data (no fields)."""
        def num(x: float) -> float | None:
            return None if not math.isfinite(x) else round(float(x), 3)

        return {"a": self.source_a, "b": self.source_b, "model_a": self.model_a, "model_b": self.model_b,
                "area": self.area, "rows": [
                    {"class": r.cls_name, "band": r.band, "bearing_deg": r.bearing_deg,
                     "tl_median_db": num(r.tl_median_db), "tl_p90_db": num(r.tl_p90_db),
                     "tl_signed_median_db": num(r.tl_signed_median_db),
                     "k_median_db": num(r.k_median_db), "k_p90_db": num(r.k_p90_db),
                     "tl_cells": r.tl_cells, "tl_one_sided": r.tl_one_sided} for r in self.rows]}


def compare_grids(a: Tables, b: Tables) -> GridComparison:
    """The differences B - A of two grids of one area.

    Parameters
    ----------
    a, b : Tables
        The two grids (``acoustics.open_tables``).

    Raises
    ------
    GridMismatchError
        The grids hold different areas, or differ in classes, bands, range or depth axes, kind
        (flat or bearing-dependent), origin or bearings; the message names what and both values.
    """
    _check_same_axes(a, b)
    radial = isinstance(a, RadialTables)
    tl_a, tl_b = a.tl_db, b.tl_db                 # (C, M, [N,] D, R)
    k_a, k_b = a.k_grid_db, b.k_grid_db           # (C, M, [N,] R)
    if not radial:  # one "bearing" for the loops below
        tl_a, tl_b, k_a, k_b = tl_a[:, :, None], tl_b[:, :, None], k_a[:, :, None], k_b[:, :, None]
    fill_a = np.isfinite(tl_a) & (tl_a < SHADOW_TL_DB)
    fill_b = np.isfinite(tl_b) & (tl_b < SHADOW_TL_DB)
    both = fill_a & fill_b
    d_tl = np.where(both, tl_b - tl_a, np.nan)
    k_both = np.isfinite(k_a) & np.isfinite(k_b)
    d_k = np.where(k_both, k_b - k_a, np.nan)
    one_sided = fill_a ^ fill_b
    rows = []
    bearings = a.bearing_deg if radial else [None]
    for ic, cls_name in enumerate(a.class_names):
        for ib, band in enumerate(a.band_names):
            if radial:
                for j, bearing in enumerate(bearings):
                    rows.append(_row(cls_name, band, float(bearing), d_tl[ic, ib, j], d_k[ic, ib, j],
                                     one_sided[ic, ib, j]))
            rows.append(_row(cls_name, band, None, d_tl[ic, ib], d_k[ic, ib], one_sided[ic, ib]))
    if radial:
        axis_name, axis_values, field = "bearing", np.asarray(a.bearing_deg, dtype=float), d_k
    else:
        axis_name, axis_values, field = "depth", np.asarray(a.depth_m, dtype=float), d_tl[:, :, 0]
    return GridComparison(source_a=a.source, source_b=b.source, model_a=a.model, model_b=b.model, area=a.area.name,
                          rows=tuple(rows), range_m=np.asarray(a.range_m, dtype=float), axis_name=axis_name,
                          axis_values=axis_values, field_db=field, class_names=a.class_names,
                          band_names=a.band_names)


def _row(cls_name: str, band: str, bearing: float | None, d_tl: np.ndarray, d_k: np.ndarray,
         one_sided: np.ndarray) -> DiffStats:
    tl = d_tl[np.isfinite(d_tl)]
    k = d_k[np.isfinite(d_k)]
    nan = float("nan")
    return DiffStats(cls_name=cls_name, band=band, bearing_deg=bearing,
                     tl_median_db=float(np.median(np.abs(tl))) if tl.size else nan,
                     tl_p90_db=float(np.percentile(np.abs(tl), 90)) if tl.size else nan,
                     k_median_db=float(np.median(np.abs(k))) if k.size else nan,
                     k_p90_db=float(np.percentile(np.abs(k), 90)) if k.size else nan,
                     tl_signed_median_db=float(np.median(tl)) if tl.size else nan,
                     tl_cells=int(tl.size), tl_one_sided=int(np.count_nonzero(one_sided)))


def _check_same_axes(a: Tables, b: Tables) -> None:
    def refuse(what: str, va, vb) -> None:
        raise GridMismatchError(f"{a.source} and {b.source} are not grids of one area on the same axes: "
                                f"{what} {va} against {vb}")

    if a.area.name != b.area.name:
        refuse("area", repr(a.area.name), repr(b.area.name))
    kind_a, kind_b = isinstance(a, RadialTables), isinstance(b, RadialTables)
    if kind_a != kind_b:
        refuse("kind", _kind(kind_a), _kind(kind_b))
    if a.class_names != b.class_names:
        refuse("classes", list(a.class_names), list(b.class_names))
    if a.band_names != b.band_names:
        refuse("bands", list(a.band_names), list(b.band_names))
    for what, xa, xb, unit in (("range axis", a.range_m, b.range_m, "m"), ("depth axis", a.depth_m, b.depth_m, "m")):
        if xa.shape != xb.shape or not np.allclose(xa, xb, rtol=0, atol=1e-6):
            refuse(what, _axis_text(xa, unit), _axis_text(xb, unit))
    if kind_a:
        same = a.bearing_deg.shape == b.bearing_deg.shape
        if not (same and np.allclose(a.bearing_deg, b.bearing_deg, rtol=0, atol=1e-6)):
            refuse("bearings", _axis_text(a.bearing_deg, "deg"), _axis_text(b.bearing_deg, "deg"))
        oa, ob = (a.origin_lat_deg, a.origin_lon_deg), (b.origin_lat_deg, b.origin_lon_deg)
        if not np.allclose(oa, ob, rtol=0, atol=1e-9):
            refuse("origin", f"{oa[0]:g} N {oa[1]:g} E", f"{ob[0]:g} N {ob[1]:g} E")
    if not math.isclose(a.observer_depth_m, b.observer_depth_m, abs_tol=1e-6):
        refuse("observer depth", f"{a.observer_depth_m:g} m", f"{b.observer_depth_m:g} m")
    for ca, cb in zip(a.classes, b.classes):
        if not math.isclose(ca.depth_m, cb.depth_m, abs_tol=1e-6):
            refuse(f"class {ca.name} depth", f"{ca.depth_m:g} m", f"{cb.depth_m:g} m")


def _kind(radial: bool) -> str:
    return "bearing-dependent" if radial else "flat"


def _axis_text(x: np.ndarray, unit: str) -> str:
    if x.size == 0:
        return "(empty)"
    return f"{x.size} values {x[0]:g}-{x[-1]:g} {unit}"
