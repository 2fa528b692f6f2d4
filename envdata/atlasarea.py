"""The area of each table of an atlas, and which positions can have one.

README "Atlases": the table of (month, position) is the bearing-dependent grid of the area with
``[origin]`` at that position and the climatology's ``month`` set. A position on land (no
elevation, or elevation >= 0 in the bathymetry file) or whose water is not deeper than the
observer is left out, with the reason, before any work.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from envdata.area import Area
from envdata.errors import AreaError
from envdata.geometry import Origin
from envdata.radials import geodesic_points
from envdata.watersources import LoadedBathymetry

#: Samples along each radial used to find the box every table's radials cross.
BOX_SAMPLES = 33


def area_for_month(area: Area, month: int) -> Area:
    """The area with its climatology's ``month`` set (month 0: the area's water as it is)."""
    if month == 0 or area.water.climatology is None:
        return area
    clim = dataclasses.replace(area.water.climatology, month=month)
    return dataclasses.replace(area, water=dataclasses.replace(area.water, climatology=clim))


def table_area(area: Area, month: int, lat_deg: float, lon_deg: float) -> Area:
    """The area of one table: ``[origin]`` at the position, the month set, no ``[atlas]``."""
    if area.origin is None:
        raise AreaError(f"area {area.name!r}: an atlas needs [origin] and [bearings]")
    one = area_for_month(area, month)
    return dataclasses.replace(one, origin=Origin(lat_deg=float(lat_deg), lon_deg=float(lon_deg)),
                               latitude_deg=float(lat_deg), longitude_deg=float(lon_deg), atlas=None)


def radial_reach(area: Area, lat_deg, lon_deg, behind_m: float = 5000.0) -> tuple[np.ndarray, np.ndarray]:
    """Points along every radial of every position (from ``-behind_m`` to ``[grid] range_max_m``):
    the box around them is the box every table reads, deg."""
    ranges = np.linspace(-behind_m, area.grid.range_max_m, BOX_SAMPLES)
    lats, lons = [np.asarray(lat_deg, dtype=float)], [np.asarray(lon_deg, dtype=float)]
    for la, lo in zip(np.ravel(lat_deg), np.ravel(lon_deg)):
        for bearing in area.bearings.bearing_deg:
            pl, po = geodesic_points(la, lo, bearing, ranges)
            lats.append(pl)
            lons.append(po)
    return np.concatenate(lats), np.concatenate(lons)


@dataclass(frozen=True, slots=True, kw_only=True)
class LeftOut:
    """A position the atlas has no table for, and why."""

    lat_deg: float
    lon_deg: float
    reason: str


def screen_positions(area: Area, lat_deg: np.ndarray, lon_deg: np.ndarray,
                     bathymetry: LoadedBathymetry | None) -> tuple[np.ndarray, list[LeftOut]]:
    """Which positions get tables: a bool mask, and the positions left out with the reason.

    A position is left out when the bathymetry has no elevation there (land in EMODnet's
    layout), when it is on land (elevation >= 0), or when the water there is not deeper than the
    observer. A flat area keeps every position.
    """
    keep = np.ones(np.shape(lat_deg), dtype=bool)
    if bathymetry is None:
        return keep, []
    elevation, no_data = bathymetry.grid.sea_elevation_at(lat_deg, lon_deg)
    out = []
    obs = area.observer.depth_m
    for i, (la, lo, e, nd) in enumerate(zip(lat_deg, lon_deg, elevation, no_data)):
        if nd:
            reason = "on land (no elevation in the bathymetry file)"
        elif e >= 0.0:
            reason = f"on land (elevation {e:.1f} m)"
        elif not obs < -e:
            reason = f"water {-e:.1f} m deep, not deeper than the observer at {obs:g} m"
        else:
            continue
        keep[i] = False
        out.append(LeftOut(lat_deg=float(la), lon_deg=float(lo), reason=reason))
    return keep, out
