"""K(r) at the observer depth alone, with or without reciprocity: far fewer receivers than a grid.

The runs are ``acoustics.builder.plan.plan_k_runs`` (one per run frequency with every source in
it, and one per class within the surface's reach, whose run carries its source pattern) and go
through the executor like a grid's (threads or a Dask cluster, optionally a resume
folder); the sensitivity members call this too, one member's runs on the worker that computes
the member. Band TL as in the grid builders (``acoustics.builder.bandruns``) and
K = spectral term - band TL (Grinenkov & Mashoshin eqs. 12-13).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from acoustics.bellhop.exe import find_bellhop
from acoustics.bellhop.shdfile import tl_from_pressure
from acoustics.builder.bandruns import BuildStats, band_tl_from_runs, freq_key, run_frequencies_hz
from acoustics.builder.plan import RECIPROCITY_MIN_DEPTH_M, k_runs, plan_k_runs
from acoustics.builder.runs import execute_runs
from acoustics.kcurve import spectral_term_db
from envdata.area import Area


def k_at_observer_db(area: Area, *, reciprocity_min_depth_m: float = RECIPROCITY_MIN_DEPTH_M,
                     workers: int = 1, scheduler: str | None = None, cache_dir: str | Path | None = None,
                     exe: str | None = None, progress: bool = False,
                     stats: BuildStats | None = None) -> np.ndarray:
    """K(r) at the observer depth, ``(class, band, range)``, dB.

    Parameters
    ----------
    area : Area
        A flat area (one profile over a flat bottom).
    reciprocity_min_depth_m : float
        Classes at least this deep by reciprocity (the source at the observer), the others
        directly (the source at the class depth): ``0`` for every class by reciprocity,
        ``math.inf`` for none.
    workers, scheduler, cache_dir, progress
        As for a grid build (``acoustics.builder.runs.iter_runs``).
    exe : str, optional
        The BELLHOP executable (default: ``find_bellhop``).
    stats : BuildStats, optional
        Filled with the runs and their BELLHOP time.
    """
    stats = stats if stats is not None else BuildStats()
    exe = exe if exe is not None else str(find_bellhop().path)
    sources, _, where = k_runs(area, reciprocity_min_depth_m)
    runs, key_of = plan_k_runs(area, reciprocity_min_depth_m)
    stats.runs = runs
    fields = execute_runs(runs, workers=workers, scheduler=scheduler, progress=progress, exe=exe,
                          cache_dir=Path(cache_dir) if cache_dir is not None else None, stats=stats)
    prop = area.propagation
    by_key = {run.key: run for run in runs}
    k = np.empty((len(area.classes), len(area.bands), area.grid.range_m().size))
    for ic, cls in enumerate(area.classes):
        isrc, ircv = where[cls.name]
        for ib, band in enumerate(area.bands):
            tl = {}
            for f in map(freq_key, run_frequencies_hz(area, band)):
                key = key_of[(cls.name, band.name, f)]
                src = 0 if by_key[key].pattern_key else isrc  # a run of its own: the class's source alone
                tl[f] = tl_from_pressure(fields[key][src, ircv], prop.tl_max_db)[None, :]
            k[ic, ib] = spectral_term_db(cls, band) - band_tl_from_runs(area, cls, band, tl)[0]
    return k


def build_k(area: Area, *, reciprocity_min_depth_m: float = RECIPROCITY_MIN_DEPTH_M, **kwargs) -> xr.DataArray:
    """`k_at_observer_db` as ``k_db(class, band, range)``, labelled; keyword arguments as there."""
    k = k_at_observer_db(area, reciprocity_min_depth_m=reciprocity_min_depth_m, **kwargs)
    return xr.DataArray(k, dims=("class", "band", "range"),
                        coords={"class": [c.name for c in area.classes], "band": [b.name for b in area.bands],
                                "range": area.grid.range_m()}, name="k_db",
                        attrs={"units": "dB", "long_name": "transfer characteristic K(r) at the observer depth",
                               "reciprocity_min_depth_m": float(reciprocity_min_depth_m)})
