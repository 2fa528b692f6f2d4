"""Propagation tables: BELLHOP and the Urick formula -> per-band, per-class TL and K(r) grids.

By role: the formulas at the root (``absorption``, ``urick``, ``kcurve``, ``levelrange``,
``detection``); ``bellhop/`` BELLHOP's formats and running; ``grid/`` what a grid is (its
dataset, contract, files and the one typed face, ``GridTables``); ``builder/`` how a grid is
built; ``plots/`` how it is drawn; ``sensitivity/`` the perturbed-environment studies;
``nx2d/`` the BELLHOP3D route kept out of the build.
"""

from acoustics.absorption import thorp_db_per_km
from acoustics.builder.flat import BuildStats, Model, build_grid, expected_source_hash
from acoustics.builder.gridfile import build_grid_file
from acoustics.builder.kobserver import build_k
from acoustics.builder.plan import plan_runs
from acoustics.errors import BellhopError, GridFileError
from acoustics.grid.io import open_grid, write_grid
from acoustics.grid.schema import check_grid
from acoustics.grid.tables import FlatTables, GridTables, RadialTables, as_tables
from acoustics.kcurve import spectral_term_db
from acoustics.urick import k_urick_db, spherical_tl_db

__all__ = ["BellhopError", "BuildStats", "FlatTables", "GridFileError", "GridTables", "Model", "RadialTables",
           "as_tables", "build_grid", "build_grid_file", "build_k", "check_grid", "expected_source_hash",
           "k_urick_db", "open_grid", "plan_runs", "spectral_term_db", "spherical_tl_db", "thorp_db_per_km",
           "write_grid"]
