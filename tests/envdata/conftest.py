"""Helpers for the range- and bearing-dependent areas: area documents and small real-layout files."""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import numpy as np
import pytest

import envdata
from tests.conftest import DATA
from tests.fixtures.layouts import (
    EMODNET_PER_DEGREE,
    WOA_LEVELS_M,
    gebco_axis_deg,
    write_emodnet,
    write_gebco,
    write_woa,
)

AREAS = Path(envdata.__file__).parent / "areas"
SAMPLE = AREAS / "data"
ORIGIN = (43.0, 5.0)


def area_document(water: dict, *, origin=ORIGIN, bearings=None, range_max_m: float = 5000.0,
                  observer_m: float = 100.0) -> dict:
    """An area-file document: the tiny Munk area with ``water`` and, unless None, an origin."""
    with open(DATA / "tiny-munk.toml", "rb") as fh:
        doc = tomllib.load(fh)
    doc = copy.deepcopy(doc)
    doc["water"] = dict(water)
    doc["observer"] = {"depth_m": observer_m}
    doc["grid"]["range_max_m"] = range_max_m
    if origin is not None:
        doc["origin"] = {"lat_deg": origin[0], "lon_deg": origin[1]}
        doc["bearings"] = bearings or {"step_deg": 90.0}
    return doc


def make_area(water: dict, folder: Path | None = None, **kwargs) -> envdata.Area:
    return envdata.parse_area(area_document(water, **kwargs), "test.toml", folder=folder)


def write_relief(path: Path, elevation, *, box=(42.8, 43.2, 4.8, 5.2), per_degree: int = 240) -> Path:
    """A GEBCO-layout file over ``box`` (south, north, west, east) with ``elevation(lat, lon)``."""
    s, n, w, e = box
    lat = gebco_axis_deg(s, n, per_degree)
    lon = gebco_axis_deg(w, e, per_degree)
    write_gebco(path, lat, lon, elevation(lat[:, None], lon[None, :]), title="test relief")
    return path


def write_dtm(path: Path, elevation, *, box=(42.8, 43.2, 4.8, 5.2), **kwargs) -> Path:
    """An EMODnet-layout file over ``box`` with ``elevation(lat, lon)`` (NaN: no value, land)."""
    s, n, w, e = box
    lat = gebco_axis_deg(s, n, EMODNET_PER_DEGREE)
    lon = gebco_axis_deg(w, e, EMODNET_PER_DEGREE)
    write_emodnet(path, lat, lon, elevation(lat[:, None], lon[None, :]), title="test DTM", **kwargs)
    return path


def write_ts(folder: Path, temperature, salinity, *, months=(8,), lat=None, lon=None,
             levels: int = 57, stem: str = "ts") -> tuple[Path, Path]:
    """WOA-layout split files; ``temperature``/``salinity`` are functions of (depth, lat, lon) grids
    returning values (NaN for no value), or arrays (time, depth, lat, lon)."""
    lat = np.arange(42.625, 43.4, 0.25) if lat is None else np.asarray(lat)
    lon = np.arange(4.625, 5.4, 0.25) if lon is None else np.asarray(lon)
    depth = WOA_LEVELS_M[:levels]
    paths = []
    for kind, field in (("t", temperature), ("s", salinity)):
        if callable(field):
            z, y, x = np.meshgrid(depth, lat, lon, indexing="ij")
            values = np.stack([field(z, y, x) for _ in months])
        else:
            values = np.asarray(field, dtype=float)
        path = folder / f"{stem}_{kind}.nc"
        write_woa(path, kind, months, depth, lat, lon, values, title="test climatology")
        paths.append(path)
    return paths[0], paths[1]


@pytest.fixture(scope="session")
def shelf_area() -> envdata.Area:
    return envdata.load_area("shelf-break")


@pytest.fixture(scope="session")
def shelf_radials(shelf_area):
    from envdata.radials import area_radials

    return area_radials(shelf_area)
