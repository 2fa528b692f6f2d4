"""A grid's BELLHOP runs as tasks of ``acoustics.builder.executor``: what a run is, and running one.

A run is one .env file; its result is the pressure field (receiver depth x range), complex64,
kept as ``KEY.npy`` in the resume folder when there is one. An arrivals run (``image`` set:
the surface at a target that is the receiver, ``acoustics.builder.surfaceimage``) is reduced
where it ran to the band TL of its rows, float32 (class, band, receiver depth, range).
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import threading
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from acoustics.bellhop.runner import run_env
from acoustics.builder import preload
from acoustics.builder.executor import ResultCache, TaskStats, run_tasks
from acoustics.builder.surfaceimage import SurfaceImage, image_tl_db


@dataclass(frozen=True, slots=True)
class Run:
    """One BELLHOP run; ``part`` of ``n_parts`` slices of one beam fan at (source depth, frequency)."""

    env: str
    freq_hz: float
    source_depth_m: float
    part: int = 0
    n_parts: int = 1
    n_beams: int = 0  # beams in this run (0: BELLHOP's automatic count)
    files: tuple[tuple[str, str], ...] = ()  # (extension, text) of files beside the .env (.bty, .ssp)
    timeout_s: float | None = None  # the run is killed after this long (None: no limit)
    all_sources: bool = False  # the field keeps a source axis (runs with several source depths)
    pattern_key: str = ""  # the source pattern's key ("": none; acoustics.builder.bandruns.SourcePattern)
    image: SurfaceImage | None = None  # an arrivals run, and what its arrivals are reduced to

    @property
    def key(self) -> str:
        h = hashlib.sha256(self.env.encode())
        for suffix, text in self.files:
            h.update(f"\0{suffix}\0".encode())
            h.update(text.encode())
        if self.image is not None:
            h.update(b"\0image\0" + self.image.digest.encode())
        return h.hexdigest()[:24]


@dataclass
class RunStats:
    runs_total: int = 0
    runs_reused: int = 0
    bellhop_seconds: float = 0.0  # sum of the BELLHOP process wall times of the runs done now
    wall_seconds: float = 0.0


def execute_run(run: Run, exe: str | None = None, slot: threading.Semaphore | None = None
                ) -> tuple[np.ndarray, float]:
    """Run one environment; return its pressure field, complex64, (receiver depth, range) of its
    one source, or (source, receiver depth, range) of an ``all_sources`` run, and BELLHOP's time.
    In incoherent and semicoherent modes |p|^2 is the summed beam intensity. An arrivals run
    returns its receivers' band TL instead (``image_tl_db``). ``slot`` is held only while BELLHOP
    runs: its files are written before and its output read (and the arrivals reduced) after, while
    the next run already goes."""
    result = run_env(run.env, exe=exe, files=dict(run.files), timeout_s=run.timeout_s, slot=slot)
    if run.image is not None:
        return image_tl_db(result.arrivals[0], run.image), result.seconds
    pressure = result.field.pressure
    return (pressure if run.all_sources else pressure[0]), result.seconds


def run_cache(folder: str | Path) -> ResultCache[tuple[np.ndarray, float]]:
    """Finished runs' pressure fields, ``KEY.npy`` each (a reused run took no BELLHOP time now)."""
    return ResultCache(folder, encode=lambda done: done[0], decode=lambda pressure: (pressure, 0.0))


def execute_runs(runs: Sequence[Run], **kwargs) -> dict[str, np.ndarray]:
    """Execute ``runs`` (deduplicated by key) and return {run.key: pressure field}."""
    return {run.key: field for run, field in iter_runs(runs, **kwargs)}


def iter_runs(runs: Sequence[Run], *, workers: int = 1, scheduler: str | None = None,
              cache_dir: Path | None = None, progress: bool = False, exe: str | None = None,
              stats: RunStats | None = None) -> Iterator[tuple[Run, np.ndarray]]:
    """Yield (run, pressure field) as runs finish: cached ones first, then as BELLHOP completes them.

    ``workers`` BELLHOP processes run at once (or the Dask cluster at ``scheduler`` runs them), so
    whatever the caller does with a result overlaps the next BELLHOP run. On this machine each
    worker has two threads and one BELLHOP slot: a run's files are written, and its output read
    and its arrivals reduced (numba, without the GIL), while the worker's next run goes. Runs
    start longest first: BELLHOP's cost grows with the beams, so the half-fan slices that balance
    the workers come last.
    """
    stats = stats if stats is not None else RunStats()
    longest_first = sorted({run.key: run for run in runs}.values(), key=lambda run: -run.n_beams)
    done = TaskStats()
    slot = threading.BoundedSemaphore(workers) if scheduler is None and workers >= 1 else None
    threads = 2 * workers if slot is not None else workers
    tasks = run_tasks(functools.partial(execute_run, exe=exe, slot=slot), longest_first, key=lambda run: run.key,
                      workers=threads, scheduler=scheduler,
                      cache=run_cache(cache_dir) if cache_dir is not None else None,
                      progress=progress, desc="BELLHOP runs", unit="run", stats=done)
    preload.start()  # the dataset's imports, beside the runs
    try:
        with contextlib.closing(tasks):  # stops the pending runs whatever the caller does
            for run, (field, seconds), reused in tasks:
                stats.runs_total, stats.runs_reused = done.total, done.reused
                if not reused:
                    stats.bellhop_seconds += seconds
                yield run, field
        preload.wait()
    finally:
        stats.runs_total, stats.runs_reused = done.total, done.reused
        stats.wall_seconds = done.wall_seconds
