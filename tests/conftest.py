"""Shared fixtures: a seeded generator, the tiny Munk area, and its real BELLHOP grid."""

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
    path = tmp_path_factory.mktemp("grid") / "tiny-munk-bellhop.nc"
    acoustics.write_grid(tiny_grid, path)
    return path
