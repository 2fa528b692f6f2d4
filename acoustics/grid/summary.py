"""What ``tmakit grids show`` says of a grid: its axes, its provenance and K(r) at a few ranges."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from acoustics.grid.face import Tables

#: Ranges at which a summary gives K, km (those within the grid's range axis).
SUMMARY_RANGES_KM = (1, 5, 10, 30, 60, 110)


@dataclass(frozen=True, slots=True, kw_only=True)
class KSummary:
    """K of one class and band at the summary's ranges, dB: the model's (NaN where the grid has
    none) and Urick's (eq. 13)."""

    cls_name: str
    band: str
    k_db: tuple[float, ...]
    k_urick_db: tuple[float, ...]


@dataclass(frozen=True, slots=True, kw_only=True)
class GridSummary:
    """A grid at a glance.

    Attributes
    ----------
    source, area, model : str
    observer_depth_m : float
    sizes : dict
        Dimension sizes.
    range_m, depth_m : tuple of float
        First and last of each axis, m.
    attrs : dict
        The global attributes but ``area_json``, as plain values.
    geometry : dict
        ``Tables.geometry()``: {} for a flat grid, the origin and radials otherwise.
    ranges_km : tuple of int
    k : tuple of KSummary
        Per class and band, in grid order.
    """

    source: str
    area: str
    model: str
    observer_depth_m: float
    sizes: dict[str, int]
    range_m: tuple[float, float]
    depth_m: tuple[float, float]
    attrs: dict
    geometry: dict
    ranges_km: tuple[int, ...]
    k: tuple[KSummary, ...]


def grid_summary(tables: Tables) -> GridSummary:
    """Summarise a grid (`GridSummary`)."""
    ds = tables.dataset
    ranges_km = tuple(r for r in SUMMARY_RANGES_KM if r * 1000 <= tables.range_m[-1])
    at_m = np.array([r * 1000.0 for r in ranges_km])
    k = []
    for ic, cls in enumerate(tables.classes):
        for ib, band in enumerate(tables.bands):
            urick = ds["k_urick_db"].sel({"class": cls.name, "band": band.name}).values
            k.append(KSummary(cls_name=cls.name, band=band.name,
                              k_db=tuple(float(v) for v in tables.k_typical_db(ic, ib, at_m)),
                              k_urick_db=tuple(float(v) for v in np.interp(at_m, tables.range_m, urick))))
    attrs = {name: (value.item() if isinstance(value, np.generic) else value)
             for name, value in ds.attrs.items() if name != "area_json"}
    return GridSummary(source=tables.source, area=tables.area.name, model=tables.model,
                       observer_depth_m=tables.observer_depth_m,
                       sizes={str(n): int(v) for n, v in ds.sizes.items()},
                       range_m=(float(tables.range_m[0]), float(tables.range_m[-1])),
                       depth_m=(float(tables.depth_m[0]), float(tables.depth_m[-1])),
                       attrs=attrs, geometry=tables.geometry(), ranges_km=ranges_km, k=tuple(k))
