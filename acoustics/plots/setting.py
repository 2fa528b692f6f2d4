"""Where a grid's area is, drawn under a figure of positions (a track, an observer's path).

By the grid's type: a flat grid says what its one column is (there is no map to draw); a
bearing-dependent grid is drawn on latitude and longitude around its origin: the bathymetry file
it records when that file is found (``acoustics.plots.bathymetry``), else the grid's own bottom
along its radials, with land shaded and the origin starred.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from acoustics.grid.atlas.follow import FollowingTables
from acoustics.grid.face import Tables
from acoustics.grid.flattables import FlatTables
from acoustics.grid.radialtables import RadialTables
from acoustics.plots.style import LAND_COLOR, ORIGIN_STYLE, contour_levels, label_depth
from envdata.radials import geodesic_points


@dataclass(frozen=True, slots=True, kw_only=True)
class Setting:
    """What was drawn: whether the axes are latitude and longitude (else x and y in km of the
    local plane), and a note for the title."""

    geographic: bool
    note: str


@functools.singledispatch
def draw_setting(tables: Tables, ax, *, radius_m: float, grid_path=None) -> Setting:
    """Draw the area under positions within ``radius_m`` of the origin (see the module)."""
    raise TypeError(f"no setting for {type(tables).__name__}")


@draw_setting.register
def _(tables: FlatTables, ax, *, radius_m: float, grid_path=None) -> Setting:
    ax.set_facecolor("#eef4fa")
    return Setting(geographic=False, note=f"area {tables.area.name}: one sound-speed profile over a flat "
                                          f"bottom at {tables.area.water.depth_m:g} m (the local plane, km)")


@draw_setting.register
def _(tables: RadialTables, ax, *, radius_m: float, grid_path=None) -> Setting:
    from acoustics.plots.bathymetry import find_bathymetry, load_around_origin
    from acoustics.plots.mapplot import draw_relief

    lat0, lon0 = tables.origin_lat_deg, tables.origin_lon_deg
    choice = find_bathymetry(tables, grid_path=grid_path)
    if choice is not None:
        draw_relief(ax, load_around_origin(choice, lat0, lon0, max(radius_m, float(tables.range_m[-1]))))
        note = f"bathymetry {choice.path.name}"
    else:
        _draw_grid_bottom(ax, tables)
        note = "the grid's bottom along its radials"
    ax.plot([lon0], [lat0], ms=11, label="grid origin", **ORIGIN_STYLE)
    ax.set_aspect(1.0 / np.cos(np.radians(lat0)))
    return Setting(geographic=True, note=f"area {tables.area.name}, {note}")


@draw_setting.register
def _(tables: FollowingTables, ax, *, radius_m: float, grid_path=None) -> Setting:
    setting = draw_setting.dispatch(RadialTables)(tables, ax, radius_m=radius_m, grid_path=grid_path)
    store = tables.store
    ax.plot(store.lon_deg, store.lat_deg, "s", ms=5, mfc="none", mec="0.25", zorder=4,
            label=f"atlas positions (month {tables.month})")
    return Setting(geographic=True, note=f"{setting.note}; the tables follow the observer through the atlas")


def _draw_grid_bottom(ax, tables: RadialTables) -> None:
    """The grid's bottom_depth_m at its radials' points, contoured on latitude and longitude."""
    lats, lons, depths = [], [], []
    for b, row in zip(tables.bearing_deg, tables.bottom_depth_m):
        lat, lon = geodesic_points(tables.origin_lat_deg, tables.origin_lon_deg, float(b), tables.range_m)
        lats.append(lat), lons.append(lon), depths.append(row)
    lat, lon, depth = (np.concatenate(v) for v in (lats, lons, depths))
    wet = np.isfinite(depth)
    ax.scatter(lon[~wet], lat[~wet], s=3, color=LAND_COLOR, lw=0, label="land")
    levels = contour_levels(depth[wet])
    if wet.sum() >= 3 and levels and tables.bearing_deg.size >= 3:
        cs = ax.tricontour(lon[wet], lat[wet], depth[wet], levels=levels, colors="k", linewidths=0.6,
                           alpha=0.6)
        ax.clabel(cs, fmt=label_depth, fontsize=6)
