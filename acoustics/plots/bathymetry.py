"""The bathymetry file behind a bearing-dependent grid: found by the grid's record, read around
the origin for a map.

A grid records its input files by name (as the area file gave them, relative to that file) and
sha256 (attribute ``input_files``, docs/formats.md "Bearing-dependent grid"); where the
area file was is not recorded. So a file is looked for, in order, as the name resolves from the
current directory, beside the grid file, and in the built-in areas' folder when the grid's area
is a built-in one; a candidate counts only when its sha256 is the recorded one. A file given
explicitly is used as it is, and the map says when it is not the one the grid was built from.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from acoustics.errors import GridFileError
from acoustics.grid.radialtables import RadialTables
from envdata.areafile import area_path, builtin_area_names
from envdata.bathymetry import ElevationGrid, open_bathymetry
from envdata.datafiles import BathymetrySource, DataFile, file_sha256
from envdata.errors import AreaError
from envdata.files import check_input_file
from envdata.radials import geodesic_points

#: The map's box reaches this much beyond the grid's last range, relative.
BOX_MARGIN = 1.08
#: Bearings at which the box's edge is sampled, deg apart.
BOX_BEARING_STEP_DEG = 5.0


@dataclass(frozen=True, slots=True, kw_only=True)
class BathymetryChoice:
    """A bathymetry file to draw, and whether it is the one the grid was built from.

    ``how`` says how it was found ("given", "as named in the grid", "beside the grid file",
    "built-in area data"); ``matches`` is True when its sha256 is the grid's record.
    """

    path: Path
    how: str
    matches: bool
    variable: str | None = None


def recorded_inputs(tables: RadialTables) -> dict[str, dict[str, str]]:
    """The grid's ``input_files`` record ({role: {"name", "sha256"}}); {} when it has none."""
    text = tables.input_files
    if text is None:
        return {}
    try:
        record = json.loads(text)
    except (TypeError, ValueError):
        record = None
    if not isinstance(record, dict) or not all(isinstance(v, dict) for v in record.values()):
        raise GridFileError(f"{tables.source}: attribute input_files is not a JSON object of "
                            f"{{role: {{name, sha256}}}}")
    return record


def find_bathymetry(tables: RadialTables, *, given: str | Path | None = None,
                    grid_path: str | Path | None = None) -> BathymetryChoice | None:
    """The bathymetry file to draw for a grid, or None when none is given or found.

    Parameters
    ----------
    tables : RadialTables
        A bearing-dependent grid.
    given : path, optional
        A file the user named: used as it is (an AreaError if it is not a regular file).
    grid_path : path, optional
        Where the grid file is, to look beside it.

    The elevation variable is the one the grid's area named (``bathymetry_variable``), if any.
    """
    water_bathymetry = tables.area.water.bathymetry
    variable = water_bathymetry.variable if water_bathymetry is not None else None
    record = recorded_inputs(tables).get("bathymetry", {})
    want = record.get("sha256")
    if given is not None:
        path = check_input_file(given, "bathymetry file", AreaError)
        return BathymetryChoice(path=path, how="given", matches=want is not None and file_sha256(path) == want,
                                variable=variable)
    name = record.get("name")
    if not name or not want:
        return None
    candidates = [(Path(name).expanduser(), "as named in the grid")]
    if grid_path is not None:
        candidates.append((Path(grid_path).parent / name, "beside the grid file"))
    area_name = tables.area.name
    if area_name in builtin_area_names():
        candidates.append((area_path(area_name).parent / name, "built-in area data"))
    for path, how in candidates:
        if path.is_file() and file_sha256(path) == want:
            return BathymetryChoice(path=path, how=how, matches=True, variable=variable)
    return None


def disk_positions(lat0_deg: float, lon0_deg: float, radius_m: float) -> tuple[np.ndarray, np.ndarray]:
    """The origin and points on the geodesic circle of ``radius_m`` around it, deg."""
    bearings = np.arange(0.0, 360.0, BOX_BEARING_STEP_DEG)
    lats, lons = [np.array([lat0_deg])], [np.array([lon0_deg])]
    for b in bearings:
        lat, lon = geodesic_points(lat0_deg, lon0_deg, float(b), [radius_m, 0.5 * radius_m])
        lats.append(lat)
        lons.append(lon)
    return np.concatenate(lats), np.concatenate(lons)


def load_around_origin(choice: BathymetryChoice, lat0_deg: float, lon0_deg: float,
                       radius_m: float) -> ElevationGrid:
    """The file's cells within (a little beyond) ``radius_m`` of the origin.

    Longitudes are returned continuous around the origin's (no jump at the file's seam).

    Raises
    ------
    AreaError
        The file cannot be read as a bathymetry file, or covers none of the disk.
    """
    lat, lon = disk_positions(lat0_deg, lon0_deg, radius_m * BOX_MARGIN)
    source = BathymetrySource(file=DataFile(path=str(choice.path), key="bathymetry"),
                              variable=choice.variable)
    with open_bathymetry(source) as bathy:
        inside = bathy.axes.contains(lat, lon)
        if not inside.any():
            raise AreaError(f"{choice.path}: covers nothing within {radius_m / 1000:g} km of the "
                            f"grid's origin {lat0_deg:.4f} N {lon0_deg:.4f} E "
                            f"({bathy.axes.describe()})")
        box = bathy.load_box(lat[inside], lon[inside])
    lon_c = lon0_deg + np.mod(box.lon_deg - lon0_deg + 180.0, 360.0) - 180.0
    order = np.argsort(lon_c)
    return ElevationGrid(path=box.path, lat_deg=box.lat_deg, lon_deg=lon_c[order],
                         elevation_m=box.elevation_m[:, order], axes=box.axes)
