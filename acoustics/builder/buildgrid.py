"""Which builder makes an area's grid: ``acoustics.build_grid``.

An area with ``[origin]`` (bearing-dependent) is built along its radials
(``acoustics.builder.radial``); one without, over its flat bottom (``acoustics.builder.flat``),
with RAM's runs where the model asks for them (``ram``, ``auto``).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from acoustics.builder.bandruns import BuildStats, Model
from acoustics.builder.flat import build_flat_grid, build_flat_ram_grid
from acoustics.builder.radial import build_radial_grid
from envdata.area import Area

if TYPE_CHECKING:  # xarray is imported beside the runs (acoustics.builder.preload)
    import xarray as xr


def build_grid(area: Area, *, model: Model | str = Model.BELLHOP, workers: int = 1,
               scheduler: str | None = None, cache_dir: str | Path | None = None,
               progress: bool = False, stats: BuildStats | None = None) -> xr.Dataset:
    """Compute the grid dataset of ``area`` (docs/formats.md "Grid file"): over its flat bottom, or
    along its radials when it has ``[origin]``.

    Parameters
    ----------
    area : Area
        The sea area.
    model : {"bellhop", "urick", "ram", "auto"}
        BELLHOP beam tracing, the Urick formula alone (TL = spherical spreading + absorption),
        the RAM parabolic equation (each band the intensity average of coherent runs), or RAM
        below a crossover frequency and BELLHOP above (``acoustics.builder.modelchoice``).
    workers : int
        BELLHOP or RAM runs at once (ignored with ``scheduler``).
    scheduler : str, optional
        Address of a Dask distributed scheduler to run the BELLHOP jobs on.
    cache_dir : path, optional
        Folder for finished runs, so that an interrupted build resumes; it is removed by the
        caller once the grid is safely written.
    progress : bool
        Show a progress bar on stderr.
    stats : BuildStats, optional
        Filled with run counts and timings.
    """
    model = Model(model)
    if area.is_bearing_dependent:
        return build_radial_grid(area, model=model, workers=workers, scheduler=scheduler,
                                 cache_dir=cache_dir, progress=progress, stats=stats)
    stats = stats if stats is not None else BuildStats()
    build = build_flat_ram_grid if model.runs_ram else build_flat_grid
    return build(area, model, workers=workers, scheduler=scheduler, cache_dir=cache_dir, progress=progress,
                 stats=stats)
