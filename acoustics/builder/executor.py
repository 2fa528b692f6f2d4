"""Running independent tasks at once: on local threads or a Dask cluster, with a resume cache.

A task is ``fn(item)``. A BELLHOP task runs BELLHOP as a subprocess, so threads run them in
parallel; a task that computes in Python itself (RAM: easypyram's numba kernels hold the GIL)
runs in worker processes instead (``processes=True``). ``workers`` is how many tasks run at once
on this machine. With ``scheduler``
(the address of a Dask distributed scheduler) the tasks run on that cluster instead and
``workers`` is ignored; their results come back unpickled. A finished result is saved in a
``ResultCache`` at once, so an interrupted job resumes without redoing it.
"""

from __future__ import annotations

import contextlib
import contextvars
import functools
import json
import logging
import multiprocessing
import os
import sys
import tempfile
import time
import uuid
import zipfile
from collections.abc import Callable, Hashable, Iterable, Iterator, Mapping
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Generic, NamedTuple, TypeVar

import numpy as np
from tqdm import tqdm

from acoustics.errors import BellhopError, WorkerLostError
from envdata.errors import InputError

log = logging.getLogger(__name__)

T = TypeVar("T")
R = TypeVar("R")

SCHEDULER_TIMEOUT = "5s"  # an unreachable scheduler fails after this
DASK_RETRIES = 1  # a task that raises is tried once more (a worker that dies costs no retry)

# What a cache stores: one array, or a record of named arrays and small JSON values
Stored = np.ndarray | Mapping[str, Any]


class TaskDone(NamedTuple, Generic[T, R]):
    """A finished task: its item, its result, and whether the result came from the cache."""

    item: T
    result: R
    reused: bool


@dataclass
class TaskStats:
    """What ``run_tasks`` did: distinct items, reused ones, workers used, wall time."""

    total: int = 0
    reused: int = 0
    workers: int = 0  # threads, or the Dask workers the scheduler had
    wall_seconds: float = 0.0


class ResultCache(Generic[R]):
    """Finished results in a folder, one file per key, each written atomically.

    An array is stored as ``KEY.npy``; a record (a mapping of names to arrays and small
    JSON-able values: numbers, strings, lists, dicts) as ``KEY.npz``, each non-array value as a
    JSON string. ``encode`` turns a result into what is stored and ``decode`` back (default: the
    result is stored as it is). The folder is made by the first ``save``; an entry that cannot
    be read is deleted and counts as missing.

    Parameters
    ----------
    folder : path
        Where the entries live.
    encode : callable, optional
        ``result -> array or record``.
    decode : callable, optional
        ``array or record -> result``.
    """

    def __init__(self, folder: str | os.PathLike, *, encode: Callable[[R], Stored] | None = None,
                 decode: Callable[[Stored], R] | None = None):
        self.folder = Path(folder)
        self._encode = encode if encode is not None else (lambda result: result)
        self._decode = decode if decode is not None else (lambda stored: stored)

    def load(self, key: str) -> R | None:
        """The result saved under ``key``, or None when there is none (or it was damaged)."""
        for path in (self.folder / f"{key}.npy", self.folder / f"{key}.npz"):
            if not path.is_file():
                continue
            try:
                return self._decode(_read(path))
            except (OSError, ValueError, KeyError, TypeError, EOFError, zipfile.BadZipFile) as exc:
                log.info("recomputing %s: damaged cache entry (%s)", path.name, exc)
                path.unlink()
        return None

    def save(self, key: str, result: R) -> Path:
        """Store ``result`` under ``key`` through a temporary file renamed into place."""
        stored = self._encode(result)
        is_array = isinstance(stored, np.ndarray)
        path = self.folder / f"{key}.{'npy' if is_array else 'npz'}"
        self.folder.mkdir(parents=True, exist_ok=True)
        fd, tmp_name = tempfile.mkstemp(prefix=f".{key}.", suffix=".tmp", dir=self.folder)
        try:
            with os.fdopen(fd, "wb") as fh:
                if is_array:
                    np.save(fh, stored, allow_pickle=False)
                else:
                    np.savez(fh, **{name: _storable(value) for name, value in stored.items()})
            os.replace(tmp_name, path)
        finally:
            if os.path.exists(tmp_name):
                os.unlink(tmp_name)
        return path


def _storable(value: Any) -> np.ndarray:
    return value if isinstance(value, np.ndarray) else np.array(json.dumps(value))


def _read(path: Path) -> Stored:
    if path.suffix == ".npy":
        return np.load(path, allow_pickle=False)
    with np.load(path, allow_pickle=False) as data:
        record = {}
        for name in data.files:
            value = data[name]
            is_json = value.ndim == 0 and value.dtype.kind == "U"
            record[name] = json.loads(str(value)) if is_json else value
        return record


def run_tasks(fn: Callable[[T], R], items: Iterable[T], *, key: Callable[[T], str], workers: int = 1,
              scheduler: str | None = None, cache: ResultCache[R] | None = None, progress: bool = False,
              desc: str = "tasks", unit: str = "task", processes: bool = False,
              stats: TaskStats | None = None, context: Any = None) -> Iterator[TaskDone[T, R]]:
    """Yield ``TaskDone(item, fn(item), reused)`` as tasks finish: reused results first.

    Items with the same key run once. Tasks start in the order of ``items``; results come in
    the order they finish. An exception raised by a task reaches the caller as itself
    (``BellhopError``, ``InputError``, ...); on a Dask cluster any other one becomes a
    ``BellhopError`` naming the task. Pending tasks are cancelled when the caller stops.

    Parameters
    ----------
    fn : callable
        The task, ``fn(item) -> result``. With ``scheduler`` it must pickle (a module-level
        function or a ``functools.partial`` of one).
    items : iterable
        The work.
    key : callable
        ``key(item) -> str``: names the item's result in the cache and on the cluster; a file
        name stem.
    workers : int
        Tasks run at once on local threads (>= 1); ignored with ``scheduler``.
    scheduler : str, optional
        Address of a Dask distributed scheduler (``tcp://HOST:PORT``) to run the tasks on.
    cache : ResultCache, optional
        Where finished results are kept and looked up.
    progress : bool
        Show a progress bar (tqdm) on stderr, labelled ``desc`` and counting ``unit``.
    processes : bool
        Run local tasks in ``workers`` worker processes (started fresh, ``spawn``) rather than
        threads: for tasks that hold the GIL. ``fn`` and the items must then pickle.
    stats : TaskStats, optional
        Filled with counts and the wall time.
    context : object, optional
        Data every task needs (an atlas's bathymetry and climatology boxes): ``fn`` is then
        called as ``fn(item, context)``. On a Dask cluster it is sent to each worker once
        (``Client.scatter(..., broadcast=True)``), not with every task.
    """
    if scheduler is None and workers < 1:
        raise InputError(f"workers: must be >= 1, got {workers}")
    stats = stats if stats is not None else TaskStats()
    start = time.perf_counter()
    unique = {}
    for item in items:
        unique.setdefault(key(item), item)
    stats.total = len(unique)
    reused, todo = [], []
    for name, item in unique.items():
        result = cache.load(name) if cache is not None else None
        if result is None:
            todo.append(item)
        else:
            reused.append(TaskDone(item, result, True))
    stats.reused = len(reused)
    if todo:
        log.info("%s: %d to run, %d reused", desc, len(todo), len(reused))
    bar = tqdm(total=len(unique), initial=len(reused), desc=desc, unit=unit, disable=not progress,
               file=sys.stderr, dynamic_ncols=True)
    try:
        yield from reused
        del reused
        if not todo:
            return
        if scheduler is None:
            stats.workers = min(workers, len(todo))
            call = fn if context is None else functools.partial(fn, context=context)
            finished = (_on_processes if processes else _on_threads)(call, todo, workers)
        else:
            finished = _on_dask(fn, todo, key, scheduler, desc, stats, context)
        with contextlib.closing(finished):  # cancels what has not run when the caller stops
            for item, result in finished:
                if cache is not None:
                    cache.save(key(item), result)
                bar.update(1)
                yield TaskDone(item, result, False)
    finally:
        bar.close()
        stats.wall_seconds = time.perf_counter() - start


def _on_threads(fn: Callable[[T], R], todo: list[T], workers: int) -> Iterator[tuple[T, R]]:
    with ThreadPoolExecutor(max_workers=min(workers, len(todo))) as pool:
        # each task runs in a copy of the caller's context (the memory limit set for the work)
        futures = {pool.submit(contextvars.copy_context().run, fn, item): item for item in todo}
        try:
            for future in as_completed(futures):
                yield futures[future], future.result()
        finally:
            for future in futures:
                future.cancel()


def _on_processes(fn: Callable[[T], R], todo: list[T], workers: int) -> Iterator[tuple[T, R]]:
    """As `_on_threads`, in fresh worker processes (``spawn``: no copy of this process's threads)."""
    context = multiprocessing.get_context("spawn")
    pool = ProcessPoolExecutor(max_workers=min(workers, len(todo)), mp_context=context)
    futures = {pool.submit(fn, item): item for item in todo}
    finished = False
    try:
        for future in as_completed(futures):
            try:
                result = future.result()
            except BrokenProcessPool:
                raise WorkerLostError("a worker process died before finishing its task (killed, or "
                                      "out of memory: see --max-gib)") from None
            yield futures[future], result
        finished = True
    finally:
        processes = list((getattr(pool, "_processes", None) or {}).values())  # gone after shutdown
        pool.shutdown(wait=finished, cancel_futures=True)
        if not finished:  # interrupted or failed: stop the tasks under way now, not when they end
            for process in processes:
                process.terminate()


def check_scheduler_address(scheduler: str) -> None:
    """Refuse what is not ``tcp://HOST:PORT`` (or ``HOST:PORT``) before Dask tries it.

    Only plain TCP is supported: TLS needs a security configuration tmakit does not take, and
    other comms (UCX, in-process) do not reach another machine. The scheduler must be a
    trusted one: its results are unpickled here.
    """
    text = scheduler[len("tcp://"):] if scheduler.startswith("tcp://") else scheduler
    host, sep, port = text.rpartition(":")
    if host.startswith("[") and host.endswith("]"):
        host = host[1:-1]  # an IPv6 address
    ok = (sep == ":" and port.isdigit() and 0 < int(port) < 65536 and host != ""
          and "://" not in host and all(ch.isalnum() or ch in ".-_:" for ch in host))
    if not ok:
        raise InputError(f"scheduler {scheduler!r}: expected tcp://HOST:PORT of a trusted Dask "
                         f"scheduler (results are unpickled from it)")


def _on_dask(fn: Callable[[T], R], todo: list[T], key: Callable[[T], str], scheduler: str, desc: str,
             stats: TaskStats, context: Any = None) -> Iterator[tuple[T, R]]:
    """The one place that talks to Dask: connect, map, collect, release, close."""
    from distributed import Client
    from distributed import as_completed as dask_as_completed

    check_scheduler_address(scheduler)
    try:
        client = Client(scheduler, timeout=SCHEDULER_TIMEOUT)
    except (OSError, TimeoutError, ValueError, TypeError) as exc:
        raise InputError(f"scheduler {scheduler}: cannot connect to a Dask scheduler "
                         f"({type(exc).__name__}: {exc})") from None
    try:
        stats.workers = len(client.scheduler_info().get("workers", {}))
        # the token keeps two jobs on one cluster from sharing results under the same item key
        token = uuid.uuid4().hex[:12]
        names = [key(item) for item in todo]
        extra = {}
        if context is not None:  # once per worker, not once per task
            extra["context"] = client.scatter(context, broadcast=True, hash=False)
        futures = client.map(fn, todo, key=[f"tmakit-{token}-{name}" for name in names], pure=False,
                             retries=DASK_RETRIES, **extra)
        by_key: dict[Hashable, tuple[T, str]] = {f.key: (item, name) for f, item, name in zip(futures, todo, names)}
        for future in dask_as_completed(futures):
            item, name = by_key[future.key]
            if future.status == "error":
                exc = future.exception()
                if isinstance(exc, (BellhopError, InputError)):
                    raise exc
                raise BellhopError(f"{desc}: {name} failed on the Dask cluster: {type(exc).__name__}: {exc}")
            result = future.result()
            future.release()
            yield item, result
    finally:
        client.close()
