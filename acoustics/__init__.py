"""Propagation tables: BELLHOP and the Urick formula -> per-band, per-class TL and K(r) grids.

By role: the formulas at the root (``absorption``, ``urick``, ``kcurve``, ``levelrange``,
``detection``); ``bellhop/`` BELLHOP's formats and running; ``grid/`` what a grid is (its
dataset, contract, files and the one typed face, ``GridTables``); ``builder/`` how a grid is
built; ``plots/`` how it is drawn; ``sensitivity/`` the perturbed-environment studies;
``nx2d/`` the BELLHOP3D route kept out of the build.
"""

from envdata.lazyexports import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(__name__, {
    "acoustics.absorption": ["thorp_db_per_km"],
    "acoustics.builder.flat": ["BuildStats", "Model", "build_grid", "expected_source_hash"],
    "acoustics.builder.gridfile": ["build_grid_file"],
    "acoustics.builder.kobserver": ["build_k"],
    "acoustics.builder.plan": ["plan_runs"],
    "acoustics.errors": ["BellhopError", "GridFileError"],
    "acoustics.grid.io": ["open_grid", "write_grid"],
    "acoustics.grid.schema": ["check_grid"],
    "acoustics.grid.tables": ["FlatTables", "GridTables", "RadialTables", "as_tables"],
    "acoustics.kcurve": ["spectral_term_db"],
    "acoustics.urick": ["k_urick_db", "spherical_tl_db"],
})
