"""Shared fixtures: a seeded generator, the tiny Munk area, and its real BELLHOP grids (flat, and
computed at one position along three radials)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import acoustics
import envdata

DATA = Path(__file__).parent / "data"
MALFORMED = DATA / "malformed"


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(12345)


@pytest.fixture(scope="session")
def tiny_area_path() -> Path:
    return DATA / "tiny-munk.toml"


@pytest.fixture(scope="session")
def tiny_area(tiny_area_path) -> envdata.Area:
    return envdata.load_area(tiny_area_path)


@pytest.fixture(scope="session")
def tiny_grid(tiny_area) -> "xr.Dataset":  # noqa: F821
    """The 2-class x 2-band grid of the tiny area, computed by the real BELLHOP."""
    return acoustics.build_grid(tiny_area, workers=2)


@pytest.fixture(scope="session")
def tiny_grid_file(tiny_grid, tmp_path_factory) -> Path:
    return _written(tiny_grid, tmp_path_factory.mktemp("grid") / "tiny-munk-bellhop.nc")


def _written(grid, path: Path) -> Path:
    """A grid written to ``path`` (a session's grid file)."""
    acoustics.write_grid(grid, path)
    return path


@pytest.fixture(scope="session")
def tiny_depth_area(tiny_area) -> envdata.Area:
    """The tiny area whose submarine's depth is uncertain (``depth_range_m`` 20-300 m): its flat
    grid also holds TL from the observer (``tl_obs_db``)."""
    doc = tiny_area.to_dict()
    doc["classes"] = [{**c, "depth_range_m": [20.0, 300.0]} if c["name"] == "SUB" else c
                      for c in doc["classes"]]
    return envdata.parse_area(doc, "tiny-depth")


@pytest.fixture(scope="session")
def tiny_depth_grid(tiny_depth_area) -> "xr.Dataset":  # noqa: F821
    """The grid of the tiny area with the submarine's depth uncertain (``tl_obs_db`` in it)."""
    return acoustics.build_grid(tiny_depth_area, workers=2)


@pytest.fixture(scope="session")
def tiny_depth_grid_file(tiny_depth_grid, tmp_path_factory) -> Path:
    return _written(tiny_depth_grid, tmp_path_factory.mktemp("depth-grid") / "tiny-munk-depth.nc")


@pytest.fixture(scope="session")
def tiny_radial_tables(tiny_area):
    """The tiny Munk area with an origin and three radials: tables computed at one position (a few
    seconds of BELLHOP)."""
    doc = tiny_area.to_dict()
    doc["origin"] = {"lat_deg": 43.0, "lon_deg": 5.0}
    doc["bearings"] = {"step_deg": 120.0}
    doc["area"] = {**doc["area"], "latitude_deg": 43.0, "longitude_deg": 5.0}
    doc["propagation"] = {**doc["propagation"], "step_m": 10.0}
    return acoustics.open_tables(acoustics.build_grid(envdata.parse_area(doc, "tiny-radial"), workers=2))


@pytest.fixture(scope="session")
def tiny_radial_grid_file(tiny_radial_tables, tmp_path_factory) -> Path:
    """The tiny Munk area's three-radial grid as a file (what ``grids plot`` and ``plan`` open)."""
    return _written(tiny_radial_tables.dataset, tmp_path_factory.mktemp("radial-grid") / "tiny-radial.nc")
