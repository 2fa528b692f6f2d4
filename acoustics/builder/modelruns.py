"""The runs of a grid with a RAM share (``--model ram`` or ``auto``), for both builders.

A "source" is what one set of runs serves: a source depth of a flat grid, a radial of a
bearing-dependent one. Its BELLHOP runs (if any) go first through the executor's threads, then
its RAM runs through worker processes (or both through one Dask cluster), all into the one
resume folder; as soon as every run of a source is in, ``on_source`` gets its TL fields by
frequency and the fields are dropped.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable, Sequence
from pathlib import Path

import numpy as np

from acoustics.bellhop.shdfile import tl_from_pressure
from acoustics.builder.bandruns import BuildStats, freq_key
from acoustics.builder.ramruns import RamRun, iter_ram_runs
from acoustics.builder.runs import Run, iter_runs
from envdata.area import Area
from envdata.limits import check_memory

Fields = dict[float, np.ndarray]


def check_model_memory(grid_bytes: float, ram_runs: Sequence[RamRun], workers: int, what: str) -> None:
    """Refuse before any run a build whose grid and largest RAM runs in flight (one per worker)
    would not fit: easypyram keeps each run's whole field (``RamRun.memory_bytes``)."""
    per_run = sorted((run.memory_bytes for run in ram_runs), reverse=True)[:max(1, workers)]
    check_memory(grid_bytes + sum(per_run), what)


def run_sources(area: Area, sources: Sequence[Hashable], ram_runs: dict[Hashable, list[RamRun]],
                bellhop_runs: Sequence[Run], bellhop_where: dict[str, tuple[Hashable, float]],
                on_source: Callable[[Hashable, Fields, Fields], None], *, workers: int = 1,
                scheduler: str | None = None, cache_dir: Path | None = None, progress: bool = False,
                exe: str | None = None, stats: BuildStats) -> None:
    """Run every source's BELLHOP and RAM runs; call ``on_source(source, ram_tl, bellhop_tl)``
    (TL fields keyed by ``freq_key``) once each source is complete.

    ``bellhop_where`` maps a BELLHOP run's key to its (source, frequency); each (source,
    frequency) is one run (no fan slices).
    """
    want_ram = {s: {run.key for run in ram_runs.get(s, [])} for s in sources}
    want_bh = {s: set() for s in sources}
    for key, (s, _) in bellhop_where.items():
        want_bh[s].add(key)
    ram_tl: dict[Hashable, Fields] = {s: {} for s in sources}
    bh_tl: dict[Hashable, Fields] = {s: {} for s in sources}
    got: dict[Hashable, set] = {s: set() for s in sources}

    def arrived(s: Hashable) -> None:
        if got[s] >= want_ram[s] | want_bh[s]:
            on_source(s, ram_tl.pop(s), bh_tl.pop(s))

    options = dict(workers=workers, scheduler=scheduler, cache_dir=cache_dir, progress=progress)
    if bellhop_runs:
        for run, field in iter_runs(bellhop_runs, exe=exe, stats=stats, **options):
            s, f = bellhop_where[run.key]
            bh_tl[s][freq_key(f)] = tl_from_pressure(field, area.propagation.tl_max_db)
            got[s].add(run.key)
    for s in sources:
        if not want_ram[s]:
            arrived(s)
    all_ram = [run for s in sources for run in ram_runs.get(s, [])]
    owners: dict[str, list[Hashable]] = {}  # identical runs (two identical radials) run once
    for s in sources:
        for run in ram_runs.get(s, []):
            owners.setdefault(run.key, []).append(s)
    for run, field in iter_ram_runs(all_ram, stats=stats, **options):
        for s in owners[run.key]:
            ram_tl[s][freq_key(run.freq_hz)] = field
            got[s].add(run.key)
            arrived(s)
