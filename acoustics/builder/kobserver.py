"""K(r) at the observer depth alone, with or without reciprocity: far fewer receivers than a grid.

The runs are ``acoustics.builder.plan.plan_k_runs`` (one per run frequency, every source in it)
and go through the executor like a grid's (threads or a Dask cluster, optionally a resume
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
from acoustics.builder.bandruns import BuildStats, band_tl_from_runs, freq_key
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
    _, _, where = k_runs(area, reciprocity_min_depth_m)
    runs = plan_k_runs(area, reciprocity_min_depth_m)
    stats.runs = runs
    fields = execute_runs(runs, workers=workers, scheduler=scheduler, progress=progress, exe=exe,
                          cache_dir=Path(cache_dir) if cache_dir is not None else None, stats=stats)
    prop = area.propagation
    tl_by_freq = {freq_key(run.freq_hz): tl_from_pressure(fields[run.key], prop.tl_max_db)
                  for run in runs}
    k = np.empty((len(area.classes), len(area.bands), area.grid.range_m().size))
    for ic, cls in enumerate(area.classes):
        isrc, ircv = where[cls.name]
        tl = {key: field[isrc, ircv][None, :] for key, field in tl_by_freq.items()}
        for ib, band in enumerate(area.bands):
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
