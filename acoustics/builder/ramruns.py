"""A grid's RAM runs as tasks of ``acoustics.builder.executor``: what a run is, and running one.

A run is one coherent RAM computation (``acoustics.ram.ram_tl_db``) of one environment (a flat
area's source depth, or a radial) at one frequency, with the default settings of the convergence
study (``RamSettings.for_environment``). Its result is TL(receiver depth, range), float32, kept as
``ram-KEY.npy`` in the resume folder when there is one. easypyram's numba kernels hold the GIL,
so local runs go to worker processes, not threads.
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.metadata
import time
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from acoustics.builder.executor import ResultCache, TaskStats, run_tasks
from acoustics.ram import RamEnvironment, RamSettings, ram_run_bytes, ram_tl_db
from acoustics.ram import run as ram_run
from acoustics.ram import settings as ram_settings


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class RamRun:
    """One RAM run: an environment at one frequency on a receiver grid.

    Attributes
    ----------
    env : RamEnvironment
        The 2-D problem, source at range 0.
    freq_hz : float
        Frequency, Hz.
    depth_m : ndarray, shape (D,)
        Receiver depths, m.
    range_m : ndarray, shape (R,)
        Receiver ranges, m.
    tl_max_db : float
        Cap where the pressure vanishes, dB.
    """

    env: RamEnvironment
    freq_hz: float
    depth_m: np.ndarray
    range_m: np.ndarray
    tl_max_db: float

    @property
    def settings(self) -> RamSettings:
        """The default settings of this run (``RamSettings.for_environment``)."""
        return RamSettings.for_environment(self.env, self.freq_hz)

    @property
    def key(self) -> str:
        """Names the run's result: a hash of everything that determines it."""
        h = hashlib.sha256(b"ram\0")
        env = self.env
        for arr in (env.bathymetry_range_m, env.bathymetry_depth_m, env.ssp_range_m, env.ssp_depth_m,
                    env.speed_mps, np.asarray(self.depth_m, dtype=float), np.asarray(self.range_m, dtype=float)):
            h.update(np.ascontiguousarray(arr, dtype=np.float64).tobytes())
            h.update(b"\0")
        h.update(repr((env.bottom, env.source_depth_m, env.end_range_m, str(env.absorption),
                       round(float(self.freq_hz), 6), self.settings, float(self.tl_max_db),
                       ram_settings_description())).encode())
        return "ram-" + h.hexdigest()[:24]

    @property
    def work(self) -> float:
        """The run's size: points of RAM's depth grid x range steps (its cost grows with it)."""
        s = self.settings
        reach_m = float(np.max(self.range_m))
        if self.env.end_range_m is not None:
            reach_m = min(reach_m, self.env.end_range_m)
        return (s.grid_depth_m / s.depth_step_m) * (reach_m / s.range_step_m)

    @property
    def memory_bytes(self) -> float:
        """Memory the run keeps at its peak, bytes (``acoustics.ram.ram_run_bytes``)."""
        return ram_run_bytes(self.env, self.depth_m, self.range_m, self.settings)


def ram_settings_description() -> dict:
    """The rule every RAM run of a grid follows, for the grid's attributes and its source hash."""
    return {
        "program": f"easypyram {importlib.metadata.version('easypyram')} (RAM 1.5, split-step Pade)",
        "depth_step_wavelengths": ram_settings.DEPTH_STEP_WAVELENGTHS,
        "range_step_wavelengths": ram_settings.RANGE_STEP_WAVELENGTHS,
        "range_step_flat_wavelengths": ram_settings.RANGE_STEP_FLAT_WAVELENGTHS,
        "wavelength_speed_mps": ram_settings.REFERENCE_SPEED_MPS,
        "pade_terms": ram_settings.PADE_TERMS,
        "stability_terms": ram_settings.STABILITY_TERMS,
        "absorbing_layer_wavelengths": ram_settings.ABSORBING_LAYER_WAVELENGTHS,
        "ssp_column_step_m": ram_run.SSP_COLUMN_STEP_M,
        "field": "coherent per frequency; band = intensity average over log-spaced frequencies",
    }


#: Runs whose total `RamRun.work` is below this go in this process, one at a time: a worker
#: process first spends ~5 s importing numpy, numba and easypyram, about what this much work takes
#: (measured ~5e6 depth points x range steps per second on this machine: a 150 m shelf at 100 Hz
#: to 3 km in 0.05 s, a 2500 m radial at 100 Hz to 30 km in 3.8 s).
IN_PROCESS_WORK = 2.5e7


def execute_ram_run(run: RamRun) -> tuple[np.ndarray, float]:
    """Compute one run: its TL(receiver depth, range), float32 (NaN below the bottom and beyond the
    environment's end), and the seconds it took."""
    start = time.perf_counter()
    tl = ram_tl_db(run.env, run.freq_hz, run.depth_m, run.range_m, run.settings, tl_max_db=run.tl_max_db)
    return tl.astype(np.float32), time.perf_counter() - start


def ram_cache(folder: str | Path) -> ResultCache[tuple[np.ndarray, float]]:
    """Finished RAM runs' TL fields (a reused run took no time now)."""
    return ResultCache(folder, encode=lambda done: done[0], decode=lambda tl: (tl, 0.0))


def iter_ram_runs(runs: Sequence[RamRun], *, workers: int = 1, scheduler: str | None = None,
                  cache_dir: Path | None = None, progress: bool = False,
                  stats=None) -> Iterator[tuple[RamRun, np.ndarray]]:
    """Yield (run, TL field) as RAM runs finish: cached ones first, then as they complete.

    Local runs go to ``workers`` processes (easypyram holds the GIL), largest first, unless
    they are too small together to pay for starting them (`IN_PROCESS_WORK`: then here, one at
    a time); with ``scheduler`` they run on that Dask cluster. ``stats`` (a ``BuildStats``)
    gains the runs and their seconds in ``ram_seconds``.
    """
    order = sorted({run.key: run for run in runs}.values(), key=lambda run: -run.work)
    here = scheduler is None and sum(run.work for run in order) < IN_PROCESS_WORK
    done = TaskStats()
    tasks = run_tasks(execute_ram_run, order, key=lambda run: run.key, workers=1 if here else workers,
                      scheduler=scheduler, cache=ram_cache(cache_dir) if cache_dir is not None else None,
                      progress=progress, desc="RAM runs", unit="run", processes=not here, stats=done)
    before_total = stats.runs_total if stats is not None else 0
    before_reused = stats.runs_reused if stats is not None else 0
    try:
        with contextlib.closing(tasks):
            for run, (field, seconds), reused in tasks:
                if stats is not None and not reused:
                    stats.ram_seconds += seconds
                yield run, field
    finally:
        if stats is not None:
            stats.runs_total = before_total + done.total
            stats.runs_reused = before_reused + done.reused
