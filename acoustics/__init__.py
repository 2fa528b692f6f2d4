"""Propagation tables: BELLHOP and the Urick formula -> per-band, per-class TL and K(r) grids."""

from acoustics.absorption import thorp_db_per_km
from acoustics.build import build_grid_file
from acoustics.errors import BellhopError, GridFileError
from acoustics.grid import BuildStats, Model, build_grid, build_k, expected_source_hash, plan_runs
from acoustics.io import open_grid, write_grid
from acoustics.schema import check_grid
from acoustics.kcurve import spectral_term_db
from acoustics.urick import k_urick_db, spherical_tl_db

__all__ = ["BellhopError", "BuildStats", "GridFileError", "Model", "build_grid", "build_grid_file", "build_k",
           "check_grid", "expected_source_hash", "k_urick_db", "open_grid", "plan_runs", "spectral_term_db",
           "spherical_tl_db", "thorp_db_per_km", "write_grid"]
