"""Radials of a range- and bearing-dependent area: the bottom and the sound speed along geodesics.

docs/formats.md "Real data" and README "Real areas". Each radial is the WGS84 geodesic
(pyproj ``Geod(ellps="WGS84")``) from the area's origin along one bearing, clockwise from true
north at the origin; negative ranges lie on the geodesic along the opposite bearing, behind the
origin (rays reach there). Along it:

- the bottom is sampled every min(``[grid] range_step_m``, the bathymetry file's cell size)
  metres, at most `MAX_SAMPLES` samples (a flat area samples every ``range_step_m``); elevations
  are interpolated bilinearly between cell centres. The radial ends at ``[grid] range_max_m``
  or where it meets land (elevation >= 0, the crossing interpolated linearly between the last
  wet and the first dry sample; or a cell with no value, EMODnet's land, the radial ending where
  it enters that cell), and begins at ``-behind_m`` or at the shore behind the origin.
  The water is at least `SHORE_DEPTH_M` deep everywhere, the shore points included.
- the sound speed is given in columns about the climatology's own spacing apart (at least one
  every `MAX_COLUMN_SPACING_M`, at least two), each the climatology's T and S interpolated
  bilinearly to the column's position (``envdata.climatology``), filled down, and converted
  with TEOS-10 with the pressure of each depth at the column's latitude. An area with one
  profile has the same column at the first and the last range.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import threading
from dataclasses import dataclass

import numpy as np

from envdata.area import Area
from envdata.bathymetry import BathymetryFile, open_bathymetry
from envdata.climatology import ClimatologyFiles, open_climatology
from envdata.errors import AreaError
from envdata.fieldchange import FieldChange, blend_months
from envdata.geogrid import LatLonAxes
from envdata.ssp import teos10_speed_mps
from envdata.watersources import WaterSources

#: netCDF-C and HDF5 are not thread-safe: threads of one process (a sensitivity study's members)
#: read the data files one at a time.
_READ_LOCK = threading.Lock()
#: Most bathymetry samples along one radial (ahead and behind the origin together).
MAX_SAMPLES = 5000
#: Sound-speed columns are at most this far apart, m.
MAX_COLUMN_SPACING_M = 10_000.0
#: Least water depth, m: a radial that meets land ends at the shore with this much water (BELLHOP
#: needs water over every bathymetry point), and shallower wet samples are deepened to it.
SHORE_DEPTH_M = 1.0
#: Spacing of the section's depths below the deepest level of a T/S profile or climatology, m
#: (T and S continue there; the speed still grows with pressure, close to linearly).
EXTENSION_STEP_M = 100.0


@dataclass(frozen=True, eq=False)
class Section:
    """The path and the bottom along one radial, before its sound speed (`Radial` adds it; the
    fields are `Radial`'s)."""

    bearing_deg: float
    range_m: np.ndarray
    lat_deg: np.ndarray
    lon_deg: np.ndarray
    bottom_depth_m: np.ndarray
    land_range_m: float | None


@dataclass(frozen=True, eq=False)
class Radial(Section):
    """The environment along one radial from the origin: bottom and sound-speed section.

    Attributes
    ----------
    bearing_deg : float
        Clockwise from true north at the origin, deg.
    range_m : ndarray, shape (R,)
        Bathymetry sample ranges along the geodesic, m, increasing; from ``-behind_m`` (or the
        shore behind the origin, if nearer) through 0 to the radial's end: ``[grid]
        range_max_m`` or where it meets land (``land_range_m``).
    lat_deg, lon_deg : ndarray, shape (R,)
        Sample positions, WGS84, deg.
    bottom_depth_m : ndarray, shape (R,)
        Water depth, m, positive down, >= `SHORE_DEPTH_M` everywhere (flat areas: constant).
    land_range_m : float or None
        Range at which the radial meets land (elevation >= 0, or a cell with no value), m; None
        if it does not.
    ssp_range_m : ndarray, shape (P,)
        Ranges of the sound-speed columns, m, increasing, the first < 0, the last the radial's
        end; P >= 2.
    ssp_depth_m : ndarray, shape (Z,)
        Depths of the section, m, from 0 to the deepest ``bottom_depth_m`` of this radial, the
        last value exactly that depth.
    speed_mps : ndarray, shape (Z, P)
        TEOS-10 sound speed at each column's position (pressure from depth at the column's
        latitude), the deepest valid T and S continued down; m/s.
    """

    ssp_range_m: np.ndarray
    ssp_depth_m: np.ndarray
    speed_mps: np.ndarray

    def __post_init__(self) -> None:
        for name in ("range_m", "lat_deg", "lon_deg", "bottom_depth_m", "ssp_range_m", "ssp_depth_m",
                     "speed_mps"):
            value = np.array(getattr(self, name), dtype=float)
            value.setflags(write=False)  # frozen all the way down
            object.__setattr__(self, name, value)

    @property
    def end_m(self) -> float:
        """The radial's last range, m."""
        return float(self.range_m[-1])

    @property
    def max_depth_m(self) -> float:
        """The deepest water along the radial, m."""
        return float(self.ssp_depth_m[-1])


def area_radials(area: Area, *, behind_m: float = 5000.0, progress: bool = False,
                 sources: WaterSources | None = None, change: FieldChange | None = None) -> list[Radial]:
    """One Radial per bearing of the area, in the area's bearing order.

    Parameters
    ----------
    area : Area
        An area with an ``[origin]`` and ``[bearings]``; its data files are read here (resolved
        against the area file's folder).
    behind_m : float
        How far behind the origin each radial starts, m (> 0): the opposite bearing's geodesic,
        which rays leaving the origin backwards reach.
    progress : bool
        Show a progress bar over the bearings on stderr.
    sources : WaterSources, optional
        The area's bathymetry and climatology already read into memory (an atlas reads the box
        of all its tables once, ``envdata.watersources``); None: the files are opened here.
    change : FieldChange, optional
        A change to the data read (``envdata.fieldchange``: relief, water, front, month), applied
        to the bathymetry and T/S boxes before the radials are sampled (sensitivity members).

    Returns
    -------
    list of Radial

    Raises
    ------
    AreaError
        No ``[origin]``; a data file missing or malformed; the origin on land or the observer
        not above the bottom there; the origin or a radial outside a file's box (naming the file,
        the bearing and the range); a radial crossing the antimeridian; a sound-speed table that
        does not reach a radial's deepest bottom.
    """
    if area.origin is None or area.bearings is None:
        raise AreaError(f"area {area.name!r}: has no [origin] and [bearings]; radials need them")
    if not (math.isfinite(behind_m) and behind_m > 0.0):
        raise ValueError(f"behind_m: must be > 0 m, got {behind_m}")
    bearings = area.bearings.bearing_deg
    water = area.water
    with contextlib.ExitStack() as stack:
        stack.enter_context(_READ_LOCK)
        if sources is not None:
            bathy, clim = sources.bathymetry, sources.climatology
            if (bathy is None) != (water.bathymetry is None) or (clim is None) != (water.climatology is None):
                raise ValueError("sources: must hold exactly the area's data files")
        else:
            bathy = stack.enter_context(open_bathymetry(water.bathymetry)) if water.bathymetry else None
            clim = stack.enter_context(open_climatology(water.climatology)) if water.climatology else None
        sections = _bottom_sections(area, bathy, behind_m, bearings, change)
        columns = [_column_positions(area, s, clim) for s in sections]
        # where the climatology is read for each column (a displaced front reads it elsewhere)
        water_at = [(r, *(change.water_positions(la, lo) if change is not None else (la, lo)))
                    for r, la, lo in columns]
        ts_field = None
        if clim is not None:
            lat = np.concatenate([c[1] for c in water_at])
            lon = np.concatenate([c[2] for c in water_at])
            _check_inside(clim.axes, clim.describe(), area, water_at, "climatology")
            ts_field = clim.load_box(lat, lon)
            if change is not None:
                ts_field = _changed_water(area, change, ts_field, lat, lon)
        iterator = zip(sections, columns, water_at)
        if progress:
            from tqdm import tqdm

            iterator = tqdm(iterator, total=len(sections), desc=f"radials {area.name}", unit="radial")
        radials = []
        for section, (ranges, lat, lon), (_, water_lat, water_lon) in iterator:
            depth, speed = _speed_section(area, section, ranges, lat, lon, ts_field, clim,
                                          water_lat, water_lon)
            radials.append(Radial(bearing_deg=section.bearing_deg, range_m=section.range_m,
                                  lat_deg=section.lat_deg, lon_deg=section.lon_deg,
                                  bottom_depth_m=section.bottom_depth_m, land_range_m=section.land_range_m,
                                  ssp_range_m=ranges, ssp_depth_m=depth, speed_mps=speed))
    return radials


def geodesic_points(lat0_deg: float, lon0_deg: float, bearing_deg: float, range_m) -> tuple[np.ndarray, np.ndarray]:
    """Positions on the WGS84 geodesic from (lat0, lon0) along ``bearing_deg``, deg.

    Negative ranges are on the geodesic along the opposite bearing. Longitudes in [-180, 180].
    """
    from pyproj import Geod

    r = np.atleast_1d(np.asarray(range_m, dtype=float))
    azimuth = np.where(r >= 0.0, bearing_deg, bearing_deg + 180.0)
    geod = Geod(ellps="WGS84")
    if r.size == 1:  # pyproj takes one point as scalars
        lon, lat, _ = geod.fwd(float(lon0_deg), float(lat0_deg), float(azimuth[0]), float(abs(r[0])))
    else:
        lon, lat, _ = geod.fwd(np.full(r.shape, lon0_deg), np.full(r.shape, lat0_deg), azimuth, np.abs(r))
    return np.atleast_1d(np.asarray(lat, dtype=float)), np.atleast_1d(np.asarray(lon, dtype=float))


def _sample_ranges(behind_m: float, end_m: float, step_m: float) -> np.ndarray:
    """Ranges from -behind_m to end_m through 0, about step_m apart, at most MAX_SAMPLES."""
    step = max(step_m, (behind_m + end_m) / (MAX_SAMPLES - 3))
    n_ahead = max(1, math.ceil(end_m / step - 1e-9))
    n_behind = max(1, math.ceil(behind_m / step - 1e-9))
    ahead = np.linspace(0.0, end_m, n_ahead + 1)
    back = np.linspace(-behind_m, 0.0, n_behind + 1)[:-1]
    return np.concatenate([back, ahead])


def _changed_water(area: Area, change: FieldChange, ts_field, lat, lon):
    """The T/S box with a member's month mixed in and its water change applied."""
    if change.other_month is not None and change.month_weight > 0.0:
        other = dataclasses.replace(area.water.climatology, month=change.other_month)
        with open_climatology(other) as clim_b:
            ts_field = blend_months(ts_field, clim_b.load_box(lat, lon), change.month_weight)
    return change.change_water(ts_field)


def _bottom_sections(area: Area, bathy: BathymetryFile | None, behind_m: float,
                     bearings: tuple[float, ...], change: FieldChange | None = None) -> list[Section]:
    origin = area.origin
    end_m = area.grid.range_max_m
    if bathy is None:
        ranges = _sample_ranges(behind_m, end_m, area.grid.range_step_m)
        out = []
        for bearing in bearings:
            lat, lon = geodesic_points(origin.lat_deg, origin.lon_deg, bearing, ranges)
            out.append(Section(bearing_deg=float(bearing), range_m=ranges, lat_deg=lat, lon_deg=lon,
                                bottom_depth_m=np.full(ranges.shape, area.water.depth_m), land_range_m=None))
        return out

    axes = bathy.axes
    if not axes.contains(origin.lat_deg, origin.lon_deg):
        raise AreaError(f"{bathy.path}: the origin {origin.lat_deg} N {origin.lon_deg} E is outside the "
                        f"bathymetry file ({axes.describe()})")
    step = min(area.grid.range_step_m, bathy.axes.cell_m(origin.lat_deg))
    ranges = _sample_ranges(behind_m, end_m, step)
    zero = int(np.flatnonzero(ranges == 0.0)[0])
    points = [geodesic_points(origin.lat_deg, origin.lon_deg, b, ranges) for b in bearings]
    # walk each radial out from the origin, both ways, to its first sample that is dry (the shore),
    # outside the file or across the file's seam; only the samples before it are needed
    walks = []
    for lat, lon in points:
        inside = axes.contains(lat, lon)
        file_lon = axes.file_lon(lon)
        seam = np.zeros(ranges.shape, dtype=bool)
        jump = np.abs(np.diff(file_lon)) > 180.0
        seam[zero + 1:] = jump[zero:]
        seam[:zero] = jump[:zero]
        walks.append((inside, seam))
    wanted = np.concatenate([inside for inside, _ in walks])
    all_lat = np.concatenate([p[0] for p in points])
    all_lon = np.concatenate([p[1] for p in points])
    grid = bathy.load_box(all_lat[wanted], all_lon[wanted])
    if change is not None and change.relief is not None:
        grid = dataclasses.replace(grid, elevation_m=change.change_relief(grid.lat_deg, grid.lon_deg,
                                                                          grid.elevation_m))
    origin_elevation, origin_no_data = (float(v[0]) for v in grid.sea_elevation_at(origin.lat_deg, origin.lon_deg))
    if origin_no_data:
        raise AreaError(f"{bathy.path}: the origin {origin.lat_deg} N {origin.lon_deg} E is in a cell with no "
                        f"elevation (land, or no data, in the file's {bathy.variable!r}): every radial "
                        f"starts on land")
    if origin_elevation >= 0.0:
        raise AreaError(f"{bathy.path}: the origin {origin.lat_deg} N {origin.lon_deg} E is on land "
                        f"(elevation {origin_elevation:.1f} m): every radial starts on land")
    if not area.observer.depth_m < -origin_elevation:
        raise AreaError(f"[observer] depth_m: {area.observer.depth_m:g} m is not above the bottom at the "
                        f"origin, {-origin_elevation:.1f} m deep in {bathy.path}")

    out = []
    for bearing, (lat, lon), (inside, seam) in zip(bearings, points, walks):
        elevation = np.full(ranges.shape, np.nan)
        no_data = np.zeros(ranges.shape, dtype=bool)
        elevation[inside], no_data[inside] = grid.sea_elevation_at(lat[inside], lon[inside])

        def land_edge(wet_m: float, dry_m: float, bearing=bearing) -> float:
            return _no_data_edge(origin.lat_deg, origin.lon_deg, bearing, wet_m, dry_m, grid)

        ahead = _walk(ranges, elevation, no_data, inside, seam, range(zero, ranges.size), bearing, bathy, axes,
                      land_edge)
        back = _walk(ranges, elevation, no_data, inside, seam, range(zero, -1, -1), bearing, bathy, axes,
                     land_edge)
        keep = slice(back[0], ahead[0] + 1)
        r = ranges[keep]
        depth = np.maximum(-elevation[keep], SHORE_DEPTH_M)
        sec_lat, sec_lon = lat[keep], lon[keep]
        land = None
        if ahead[1] is not None:  # the shore ahead: one more point, at the crossing
            land = ahead[1]
            sl, so = geodesic_points(origin.lat_deg, origin.lon_deg, bearing, [land])
            r, depth = np.append(r, land), np.append(depth, SHORE_DEPTH_M)
            sec_lat, sec_lon = np.append(sec_lat, sl), np.append(sec_lon, so)
        if back[1] is not None:  # the shore behind
            sl, so = geodesic_points(origin.lat_deg, origin.lon_deg, bearing, [back[1]])
            r, depth = np.insert(r, 0, back[1]), np.insert(depth, 0, SHORE_DEPTH_M)
            sec_lat, sec_lon = np.insert(sec_lat, 0, sl), np.insert(sec_lon, 0, so)
        out.append(Section(bearing_deg=float(bearing), range_m=r, lat_deg=sec_lat, lon_deg=sec_lon,
                            bottom_depth_m=depth, land_range_m=land))
    return out


def _walk(ranges, elevation, no_data, inside, seam, order, bearing, bathy, axes,
          land_edge) -> tuple[int, float | None]:
    """Walk from the origin (the first index of ``order``) to the last wet sample before the
    shore or the end; returns its index and the shore's range (None without one).

    The shore is where the elevation crosses 0 (linear between the last wet and the first dry
    sample) or, for a cell with no value (land in EMODnet's layout), the edge of that cell
    (``land_edge(last wet range, first dry range)``).
    """
    last = None
    for i in order:
        if seam[i]:
            raise AreaError(f"{bathy.path}: the radial at bearing {bearing:g} deg crosses the antimeridian "
                            f"at range {ranges[i]:.0f} m, and the file does not continue across it "
                            f"({axes.describe()}); choose an origin or range_max_m that keep the radials on "
                            f"one side")
        if not inside[i]:
            raise AreaError(f"{bathy.path}: the radial at bearing {bearing:g} deg leaves the bathymetry "
                            f"file at range {ranges[i]:.0f} m ({axes.describe()}); use a larger file or "
                            f"a smaller [grid] range_max_m")
        if no_data[i]:
            return last, float(land_edge(ranges[last], ranges[i]))
        if elevation[i] >= 0.0:
            e0, e1 = elevation[last], elevation[i]
            shore = ranges[last] + (ranges[i] - ranges[last]) * (e0 / (e0 - e1))
            return last, float(shore)
        last = i
    return last, None


#: The edge of a cell with no value is found along the radial to within this, m.
LAND_EDGE_TOLERANCE_M = 1.0


def _no_data_edge(lat0_deg: float, lon0_deg: float, bearing_deg: float, wet_m: float, dry_m: float,
                  grid) -> float:
    """Range between ``wet_m`` (the nearest cell has a value) and ``dry_m`` (it has none) where
    the radial enters the cell with no value, by bisection to `LAND_EDGE_TOLERANCE_M`, m."""
    while abs(dry_m - wet_m) > LAND_EDGE_TOLERANCE_M:
        mid = 0.5 * (wet_m + dry_m)
        lat, lon = geodesic_points(lat0_deg, lon0_deg, bearing_deg, [mid])
        if grid.sea_elevation_at(lat, lon)[1][0]:
            dry_m = mid
        else:
            wet_m = mid
    return 0.5 * (wet_m + dry_m)  # strictly between the last wet sample and the first dry one


def _column_positions(area: Area, section: Section, clim: ClimatologyFiles | None):
    """Ranges and positions of a radial's sound-speed columns."""
    first, end = float(section.range_m[0]), float(section.range_m[-1])
    if clim is None:
        ranges = np.array([first, end])
    else:
        spacing = min(MAX_COLUMN_SPACING_M, clim.axes.cell_m(area.origin.lat_deg))
        n = max(2, math.ceil((end - first) / spacing - 1e-9) + 1)
        ranges = np.linspace(first, end, n)
    lat, lon = geodesic_points(area.origin.lat_deg, area.origin.lon_deg, section.bearing_deg, ranges)
    return ranges, lat, lon


def _check_inside(axes: LatLonAxes, describe: str, area: Area, columns, what: str) -> None:
    if not axes.contains(area.origin.lat_deg, area.origin.lon_deg):
        raise AreaError(f"{describe}: the origin {area.origin.lat_deg} N {area.origin.lon_deg} E is "
                        f"outside the {what}")
    for bearing, (ranges, lat, lon) in zip(area.bearings.bearing_deg, columns):
        inside = axes.contains(lat, lon)
        if not inside.all():
            i = int(np.argmin(inside))
            raise AreaError(f"{describe}: the radial at bearing {bearing:g} deg leaves the {what} at "
                            f"range {ranges[i]:.0f} m ({lat[i]:.4f} N {lon[i]:.4f} E)")
        file_lon = axes.file_lon(lon)
        if np.any(np.abs(np.diff(file_lon)) > 180.0):
            raise AreaError(f"{describe}: the radial at bearing {bearing:g} deg crosses the antimeridian, "
                            f"and the {what} does not continue across it")


def one_profile(area: Area, max_depth_m: float, where: str) -> tuple[np.ndarray, np.ndarray] | None:
    """The area's one profile (a table, or T and S of a cast continued down) to ``max_depth_m``:
    the section's depths and the speed there, m/s; None where the water is a climatology's.
    A table that stops above the deepest bottom is an AreaError (``where``: which bottom)."""
    water = area.water
    if water.ssp is not None:
        ssp = water.ssp
        if ssp.bottom_m < max_depth_m - 1e-6:
            raise AreaError(f"[water] sound-speed profile: ends at {ssp.bottom_m:g} m, above the deepest "
                            f"bottom{where}; give a table to that depth, or T and S (which continue down)")
        z = section_depths(ssp.depth_m, max_depth_m, extend=False)
        return z, np.interp(z, ssp.depth_m, ssp.speed_mps)
    if water.ts is not None:
        z = section_depths(water.ts.depth_m, max_depth_m, extend=True)
        return z, water.ts.speed_mps(z, latitude_deg=area.origin.lat_deg, longitude_deg=area.origin.lon_deg)
    return None


def column_speeds(ts_field, columns, points, max_depth_m: float) -> tuple[np.ndarray, np.ndarray]:
    """Sound speed down the climatology's columns (TEOS-10): the section's depths (`section_depths`,
    continued down) and the speed there at each column, (Z, P), m/s.

    ``columns`` (lat, lon) are where T and S are read (the water of each point), ``points``
    (lat, lon) where the speed is (TEOS-10 takes the pressure and the absolute salinity there).
    """
    levels = ts_field.depth_m
    z = section_depths(levels, max_depth_m, extend=True)
    t_levels, s_levels = ts_field.columns_at(*columns)  # (L, P)
    t = np.stack([np.interp(z, levels, t_levels[:, j]) for j in range(t_levels.shape[1])], axis=1)
    s = np.stack([np.interp(z, levels, s_levels[:, j]) for j in range(s_levels.shape[1])], axis=1)
    lat, lon = points
    return z, teos10_speed_mps(z[:, None], t, s, latitude_deg=lat[None, :], longitude_deg=lon[None, :])


def section_depths(levels_m, max_depth_m: float, extend: bool) -> np.ndarray:
    """Depths of a section: 0, the levels above ``max_depth_m``, (with ``extend``) every
    `EXTENSION_STEP_M` below the deepest level, and ``max_depth_m`` itself, m."""
    levels = np.asarray(levels_m, dtype=float)
    z = levels[levels < max_depth_m]
    if z.size == 0 or z[0] > 0.0:
        z = np.concatenate([[0.0], z])
    if extend and levels[-1] < max_depth_m:
        below = np.arange(levels[-1] + EXTENSION_STEP_M, max_depth_m, EXTENSION_STEP_M)
        z = np.concatenate([z, below[below < max_depth_m - 1e-6]])
    return np.append(z, float(max_depth_m))


def _speed_section(area: Area, section: Section, ranges, lat, lon, ts_field, clim, water_lat, water_lon):
    max_depth = float(np.max(section.bottom_depth_m))
    one = one_profile(area, max_depth, f", {max_depth:.1f} m, of the radial at bearing {section.bearing_deg:g} deg")
    if one is not None:
        z, column = one
        return z, np.repeat(column[:, None], ranges.size, axis=1)
    z, speed = column_speeds(ts_field, (water_lat, water_lon), (lat, lon), max_depth)
    if not np.all(np.isfinite(speed)):
        raise AreaError(f"{clim.describe()}: TEOS-10 gives no sound speed on the radial at bearing "
                        f"{section.bearing_deg:g} deg (T or S out of range)")
    return z, speed
