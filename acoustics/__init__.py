"""Propagation tables: BELLHOP and the Urick formula -> per-band, per-class TL and K(r) grids.

By role: the formulas at the root (``absorption``, ``urick``, ``kcurve``, ``levelrange``,
``detection``); ``bellhop/`` and ``ram/`` a model's formats and running; ``grid/`` what tables
are (the grid dataset, its contract and files, the face ``Tables`` every reader asks, and
``grid/atlas/`` an atlas's store); ``builder/`` how tables are built; ``plots/`` how they are
drawn; ``sensitivity/`` the perturbed-environment studies; ``nx2d/`` the BELLHOP3D route kept
out of the build.

One way in, as xarray's ``open_dataset``: ``open_tables(path)`` answers for a grid file or an
atlas (or a grid dataset in memory) with the face.
"""

from envdata.lazyexports import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(__name__, {
    "acoustics.absorption": ["thorp_db_per_km"],
    "acoustics.builder.bandruns": ["BuildStats", "Model"],
    "acoustics.builder.buildgrid": ["build_grid"],
    "acoustics.builder.flat": ["expected_source_hash"],
    "acoustics.builder.gridfile": ["build_grid_file"],
    "acoustics.builder.kobserver": ["build_k"],
    "acoustics.builder.plan": ["plan_runs"],
    "acoustics.errors": ["BellhopError", "GridFileError"],
    "acoustics.grid.face": ["Tables"],
    "acoustics.grid.io": ["write_grid"],
    "acoustics.grid.opentables": ["open_tables"],
    "acoustics.grid.schema": ["check_grid"],
    "acoustics.kcurve": ["spectral_term_db"],
    "acoustics.urick": ["k_urick_db", "spherical_tl_db"],
})
