"""Planning and executing the BELLHOP runs a grid needs: in threads, or on a Dask cluster.

A run is one .env file; its result is the pressure field (receiver depth x range), complex64. Results
are stored as .npy files in a cache folder when one is given, so that an interrupted build
resumes without redoing finished runs.
"""

from __future__ import annotations

import hashlib
import logging
import os
import sys
import time
from collections.abc import Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from tqdm import tqdm

from acoustics.bellhop.runner import run_env
from acoustics.errors import BellhopError
from envdata.errors import InputError

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class Run:
    """One BELLHOP run; ``part`` of ``n_parts`` slices of one beam fan at (source depth, frequency)."""

    env: str
    freq_hz: float
    source_depth_m: float
    part: int = 0
    n_parts: int = 1
    n_beams: int = 0  # beams in this run (0: BELLHOP's automatic count)

    @property
    def key(self) -> str:
        return hashlib.sha256(self.env.encode()).hexdigest()[:24]


@dataclass
class RunStats:
    runs_total: int = 0
    runs_reused: int = 0
    bellhop_seconds: float = 0.0  # sum of the BELLHOP process wall times of the runs done now
    wall_seconds: float = 0.0


def execute_run(env: str, exe: str | None = None) -> tuple[np.ndarray, float]:
    """Run one environment; return its pressure field (first source depth), complex64, and
    BELLHOP's time. In incoherent and semicoherent modes |p|^2 is the summed beam intensity."""
    result = run_env(env, exe=exe)
    return result.field.pressure[0], result.seconds


def execute_runs(runs: Sequence[Run], **kwargs) -> dict[str, np.ndarray]:
    """Execute ``runs`` (deduplicated by key) and return {run.key: pressure field}."""
    return {run.key: tl for run, tl in iter_runs(runs, **kwargs)}


def iter_runs(runs: Sequence[Run], *, workers: int = 1,
              scheduler: str | None = None, cache_dir: Path | None = None,
              progress: bool = False, exe: str | None = None,
              stats: RunStats | None = None) -> Iterator[tuple[Run, np.ndarray]]:
    """Yield (run, pressure field) as runs finish: cached ones first, then as BELLHOP completes them.

    BELLHOP always runs in worker threads (one per worker), so whatever the caller does with a
    result overlaps the next BELLHOP run.
    """
    stats = stats if stats is not None else RunStats()
    start = time.perf_counter()
    unique = {run.key: run for run in runs}
    stats.runs_total = len(unique)
    todo = []
    cached = []
    for key, run in unique.items():
        path = cache_dir / f"{key}.npy" if cache_dir is not None else None
        if path is not None and path.exists():
            try:
                cached.append((run, np.load(path)))
                continue
            except (OSError, ValueError):
                path.unlink()  # a damaged cache entry is simply recomputed
        todo.append(run)
    stats.runs_reused = len(cached)
    if todo:
        log.info("running BELLHOP %d times (%d reused)", len(todo), stats.runs_reused)
    bar = tqdm(total=len(unique), initial=len(cached), desc="BELLHOP runs", unit="run",
               disable=not progress, file=sys.stderr, dynamic_ncols=True)

    def keep(run: Run, tl: np.ndarray, seconds: float) -> tuple[Run, np.ndarray]:
        stats.bellhop_seconds += seconds
        if cache_dir is not None:
            cache_dir.mkdir(parents=True, exist_ok=True)  # only once a run has finished
            tmp = cache_dir / f".{run.key}.{os.getpid()}.npy"
            np.save(tmp, tl)
            os.replace(tmp, cache_dir / f"{run.key}.npy")
        bar.update(1)
        return run, tl

    try:
        yield from cached
        del cached
        if scheduler is not None:
            for run, tl, seconds in _execute_dask(todo, scheduler, exe):
                yield keep(run, tl, seconds)
        elif todo:
            # longest first (BELLHOP's cost grows with the beams), so the half-fan slices that
            # balance the workers come last
            todo = sorted(todo, key=lambda run: -run.n_beams if run.n_beams else 0)
            with ThreadPoolExecutor(max_workers=max(1, workers)) as pool:
                futures = {pool.submit(execute_run, run.env, exe): run for run in todo}
                try:
                    for future in as_completed(futures):
                        yield keep(futures[future], *future.result())
                finally:
                    for future in futures:
                        future.cancel()
    finally:
        bar.close()
        stats.wall_seconds = time.perf_counter() - start


def _execute_dask(todo: Sequence[Run], scheduler: str,
                  exe: str | None) -> Iterator[tuple[Run, np.ndarray, float]]:
    from distributed import Client, as_completed as dask_as_completed

    try:
        client = Client(scheduler, timeout="5s")
    except (OSError, TimeoutError) as exc:
        raise InputError(f"--scheduler {scheduler}: cannot connect to a Dask scheduler "
                         f"({type(exc).__name__}: {exc})") from None
    try:
        futures = client.map(execute_run, [run.env for run in todo], exe=exe,
                             key=[f"bellhop-{run.key}" for run in todo], retries=2)
        by_key = {future.key: run for future, run in zip(futures, todo)}
        for future in dask_as_completed(futures):
            if future.status == "error":
                exc = future.exception()
                if isinstance(exc, BellhopError):
                    raise exc
                raise BellhopError(f"BELLHOP run failed on the Dask cluster: {exc}")
            yield (by_key[future.key], *future.result())
    finally:
        client.close()
