"""Planning and executing the BELLHOP runs a grid needs: in threads, or on a Dask cluster.

A run is one .env file; its result is the TL field (receiver depth x range) as float32. Results
are stored as .npy files in a cache folder when one is given, so that an interrupted build
resumes without redoing finished runs.
"""

from __future__ import annotations

import hashlib
import logging
import os
import sys
import time
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from tqdm import tqdm

from acoustics.bellhop.runner import run_env
from acoustics.bellhop.shdfile import tl_from_pressure
from acoustics.errors import BellhopError
from envdata.errors import InputError

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class Run:
    env: str
    freq_hz: float
    source_depth_m: float

    @property
    def key(self) -> str:
        return hashlib.sha256(self.env.encode()).hexdigest()[:24]


@dataclass
class RunStats:
    runs_total: int = 0
    runs_reused: int = 0
    bellhop_seconds: float = 0.0  # sum of the BELLHOP process wall times of the runs done now
    wall_seconds: float = 0.0


def execute_run(env: str, tl_max_db: float, exe: str | None = None) -> tuple[np.ndarray, float]:
    """Run one environment; return its TL field (first source depth), float32, and BELLHOP's time."""
    result = run_env(env, exe=exe)
    tl = tl_from_pressure(result.field.pressure[0], tl_max_db).astype(np.float32)
    return tl, result.seconds


def execute_runs(runs: Sequence[Run], *, tl_max_db: float, workers: int = 1,
                 scheduler: str | None = None, cache_dir: Path | None = None,
                 progress: bool = False, exe: str | None = None,
                 stats: RunStats | None = None) -> dict[str, np.ndarray]:
    """Execute ``runs`` (deduplicated by key) and return {run.key: TL field}."""
    stats = stats if stats is not None else RunStats()
    start = time.perf_counter()
    unique = {run.key: run for run in runs}
    stats.runs_total = len(unique)
    results: dict[str, np.ndarray] = {}
    if cache_dir is not None:
        cache_dir.mkdir(parents=True, exist_ok=True)
        for key in unique:
            path = cache_dir / f"{key}.npy"
            if path.exists():
                try:
                    results[key] = np.load(path)
                except (OSError, ValueError):
                    path.unlink()  # a damaged cache entry is simply recomputed
    stats.runs_reused = len(results)
    todo = [run for key, run in unique.items() if key not in results]
    if todo:
        log.info("running BELLHOP %d times (%d reused)", len(todo), stats.runs_reused)
    bar = tqdm(total=len(unique), initial=len(results), desc="BELLHOP runs", unit="run",
               disable=not progress, file=sys.stderr, dynamic_ncols=True)

    def keep(run: Run, tl: np.ndarray, seconds: float) -> None:
        results[run.key] = tl
        stats.bellhop_seconds += seconds
        if cache_dir is not None:
            tmp = cache_dir / f".{run.key}.{os.getpid()}.npy"
            np.save(tmp, tl)
            os.replace(tmp, cache_dir / f"{run.key}.npy")
        bar.update(1)

    try:
        if scheduler is not None:
            _execute_dask(todo, tl_max_db, scheduler, exe, keep)
        elif workers <= 1:
            for run in todo:
                keep(run, *execute_run(run.env, tl_max_db, exe))
        else:
            with ThreadPoolExecutor(max_workers=workers) as pool:
                futures = {pool.submit(execute_run, run.env, tl_max_db, exe): run for run in todo}
                try:
                    for future in as_completed(futures):
                        keep(futures[future], *future.result())
                except BaseException:
                    for future in futures:
                        future.cancel()
                    raise
    finally:
        bar.close()
        stats.wall_seconds = time.perf_counter() - start
    return results


def _execute_dask(todo: Sequence[Run], tl_max_db: float, scheduler: str, exe: str | None,
                  keep: Callable[[Run, np.ndarray, float], None]) -> None:
    from distributed import Client, as_completed as dask_as_completed

    try:
        client = Client(scheduler, timeout="5s")
    except (OSError, TimeoutError) as exc:
        raise InputError(f"--scheduler {scheduler}: cannot connect to a Dask scheduler "
                         f"({type(exc).__name__}: {exc})") from None
    try:
        futures = client.map(execute_run, [run.env for run in todo], tl_max_db=tl_max_db, exe=exe,
                             key=[f"bellhop-{run.key}" for run in todo], retries=2)
        by_key = {future.key: run for future, run in zip(futures, todo)}
        for future in dask_as_completed(futures):
            if future.status == "error":
                exc = future.exception()
                if isinstance(exc, BellhopError):
                    raise exc
                raise BellhopError(f"BELLHOP run failed on the Dask cluster: {exc}")
            keep(by_key[future.key], *future.result())
    finally:
        client.close()
