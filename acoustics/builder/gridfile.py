"""Grid files built once: an up-to-date file is reused, an interrupted build resumes.

The finished BELLHOP runs of a build are kept in ``.NAME.partial-HASH/`` beside the output file
NAME (HASH: the start of the grid's ``source_hash``) and removed once the file is written.
"""

from __future__ import annotations

import os
import shutil
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import envdata
from acoustics.builder.bandruns import BuildStats, Model, incoherent_surface_notes
from acoustics.builder.buildgrid import build_grid
from acoustics.builder.flat import expected_source_hash
from acoustics.errors import GridFileError
from acoustics.grid.io import write_grid

if TYPE_CHECKING:  # xarray is imported beside the runs (acoustics.builder.preload)
    import xarray as xr


@dataclass(frozen=True, slots=True, kw_only=True)
class GridFileResult:
    """What ``build_grid_file`` did.

    Attributes
    ----------
    file : Path
    area : str
    model : Model
    up_to_date : bool
        The file was current and reused: nothing was computed.
    source_hash : str
    runs, runs_reused : int
        BELLHOP runs of the build, and those taken from the resume folder.
    bellhop_seconds, ram_seconds, wall_seconds : float
        BELLHOP's and RAM's time of the runs done now, and the build's wall time, s.
    dims : dict
        The grid's dimension sizes ({} when the file was reused).
    notes : list of str
        What the user should know of the grid's physics: a near-surface class in incoherent
        beams, and how far off its levels are (``bandruns.incoherent_surface_notes``).
    dataset : xarray.Dataset or None
        The grid just built and written, in memory (None when the file was reused): what a caller
        reads next without opening the file again.
    """

    file: Path
    area: str
    model: Model
    up_to_date: bool
    source_hash: str
    runs: int = 0
    runs_reused: int = 0
    bellhop_seconds: float = 0.0
    ram_seconds: float = 0.0
    wall_seconds: float = 0.0
    dims: dict[str, int] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    dataset: xr.Dataset | None = field(default=None, repr=False, compare=False)


def resume_dir(out: str | os.PathLike, digest: str) -> Path:
    """The resume folder of output file ``out`` whose numbers hash to ``digest``."""
    out = Path(out)
    return out.parent / f".{out.name}.partial-{digest[:12]}"


def remove_cache(cache_dir: str | os.PathLike) -> None:
    """Remove a resume folder (once the file it served is written); a missing one is fine."""
    shutil.rmtree(cache_dir, ignore_errors=True)


def build_grid_file(area: envdata.Area | str | os.PathLike, out: str | os.PathLike | None = None, *,
                    model: Model | str = Model.BELLHOP, workers: int = 1, scheduler: str | None = None,
                    force: bool = False, progress: bool = False) -> GridFileResult:
    """Build the grid file of an area, or reuse it when its ``source_hash`` is current.

    Parameters
    ----------
    area : Area, str or path
        The area, a built-in area name or an area TOML file.
    out : path, optional
        Grid file to write; default ``AREA-MODEL.nc`` in the working directory.
    model : {"bellhop", "urick", "ram", "auto"}
        As in ``build_grid``.
    workers : int
        BELLHOP or RAM runs at once on this machine (>= 1); ignored with ``scheduler``.
    scheduler : str, optional
        Address of a Dask distributed scheduler to run the BELLHOP runs on.
    force : bool
        Rebuild even when the file is up to date (an unreadable file is always rebuilt).
    progress : bool
        Show a progress bar on stderr.

    Returns
    -------
    GridFileResult
    """
    if workers < 1:
        raise envdata.InputError(f"workers: must be >= 1, got {workers}")
    model = Model(model)
    area = area if isinstance(area, envdata.Area) else envdata.load_area(area)
    out = Path(out) if out is not None else Path(f"{area.name}-{model}.nc")
    digest = expected_source_hash(area, model)
    notes = incoherent_surface_notes(area) if model.runs_bellhop else []
    if out.exists() and not force:
        from acoustics.grid.opentables import open_tables  # xarray: a fresh build imports it beside its runs

        try:
            existing = open_tables(out)
        except GridFileError:
            existing = None  # unreadable: rebuilt below
        if existing is not None and existing.dataset.attrs.get("source_hash") == digest:
            return GridFileResult(file=out, area=area.name, model=model, up_to_date=True,
                                  source_hash=digest, notes=notes)
    cache_dir = resume_dir(out, digest)
    stats = BuildStats()
    start = time.perf_counter()
    ds = build_grid(area, model=model, workers=workers, scheduler=scheduler,
                    cache_dir=cache_dir if model is not Model.URICK else None, progress=progress, stats=stats)
    write_grid(ds, out)
    remove_cache(cache_dir)
    return GridFileResult(file=out, area=area.name, model=model, up_to_date=False, source_hash=digest,
                          runs=stats.runs_total, runs_reused=stats.runs_reused,
                          bellhop_seconds=stats.bellhop_seconds, ram_seconds=stats.ram_seconds,
                          wall_seconds=time.perf_counter() - start,
                          dims={str(k): int(v) for k, v in ds.sizes.items()}, notes=notes, dataset=ds)
