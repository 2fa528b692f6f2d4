"""Building the propagation grid of an area: TL(class, band, depth, range), K(r), Urick K(r).

The BELLHOP route runs one job per (source depth, run frequency): the classes' depths, and, when
a class has a ``depth_range_m`` (its target's depth is not known), the observer's depth for
``tl_obs_db`` (TL from the observer to every depth: by reciprocity, K with the target at any
depth; a class at the observer's depth shares its runs). In incoherent mode with
a fixed beam fan, frequency changes TL almost only through volume absorption, so by default one
run at each band's centre serves the whole band: TL(f) = TL(f_c) + (alpha(f) - alpha(f_c)) r.
Otherwise every quadrature frequency of every band is its own run.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from acoustics.bellhop.envfile import env_text
from acoustics.bellhop.exe import find_bellhop
from acoustics.bellhop.shdfile import tl_from_pressure
from acoustics.builder.bandruns import (
    BuildStats,
    Model,
    band_tl_from_runs,
    freq_key,
    run_frequencies_hz,
    run_pattern,
)
from acoustics.builder.imageruns import plan_image_run, with_image_rows
from acoustics.builder.modelchoice import (
    band_plans,
    bellhop_run_hz,
    grid_source_hash,
    planned_band_tl_db,
    ram_run_hz,
    with_ram_attrs,
)
from acoustics.builder.modelruns import check_model_memory, run_sources
from acoustics.builder.plan import plan_runs, receiver_depths_m, source_speed_mps
from acoustics.builder.ramruns import RamRun
from acoustics.builder.runs import Run, iter_runs
from acoustics.kcurve import spectral_term_db
from acoustics.ram import RamEnvironment
from acoustics.surface import SURFACE_ROW_M, with_surface_rows
from acoustics.urick import spherical_tl_db, urick_tables
from envdata.area import Area, TlMode
from envdata.limits import check_memory

if TYPE_CHECKING:  # xarray is imported beside the runs (acoustics.builder.preload)
    import xarray as xr


def combined_tl_db(parts: list[np.ndarray], mode: TlMode, tl_max_db: float) -> np.ndarray:
    """TL of a whole beam fan from its slices' pressure fields (see ``fan_slices``), dB."""
    if mode is TlMode.COHERENT:
        return tl_from_pressure(np.sum(parts, axis=0), tl_max_db)
    intensity = np.sum([np.abs(p).astype(np.float64) ** 2 for p in parts], axis=0)
    return -10.0 * np.log10(np.maximum(intensity, 10.0 ** (-tl_max_db / 10.0)))


def _tl_by_freq(area: Area, runs: list[Run], fields: dict[str, np.ndarray], rows=slice(None)) -> dict:
    """{run frequency: TL field} of one source depth's runs, slices combined."""
    groups: dict[float, list[np.ndarray]] = {}
    for run in {run.key: run for run in runs}.values():  # each slice once
        groups.setdefault(freq_key(run.freq_hz), []).append(fields[run.key][rows])
    prop = area.propagation
    return {f: combined_tl_db(parts, prop.mode, prop.tl_max_db) for f, parts in groups.items()}


def _assemble(area: Area, runs: list[Run], fill, *, observer_end: bool, image=None, **run_options) -> None:
    """Run ``runs`` and call ``fill(end, ic, ib, band_tl)`` for each (class, band) as soon as its
    runs are in, ``end`` "source" for the runs from the class's depth and "observer" for those
    from the observer's, dropping each run's field once nothing pending needs it.

    ``image`` is the arrivals run from the observer, (receiver rows, run)
    (``acoustics.builder.imageruns``): the "observer" end's band TL waits for it and takes those
    rows from it (the surface at the target's end)."""
    pending = {}
    ends = ["source"] + (["observer"] if observer_end else [])
    for end in ends:
        for ic, cls in enumerate(area.classes):
            sd = cls.depth_m if end == "source" else area.observer.depth_m
            for ib, band in enumerate(area.bands):
                wanted = set()
                for f in map(freq_key, run_frequencies_hz(area, band)):
                    pattern = (run_pattern(area, cls, band, f, sd, source_speed_mps(area, sd))
                               if end == "source" else None)
                    wanted.add((f, pattern.key if pattern is not None else ""))
                keys = {run.key for run in runs if run.source_depth_m == sd
                        and (freq_key(run.freq_hz), run.pattern_key) in wanted}
                if end == "observer" and image is not None:
                    keys.add(image[1].key)
                pending[(end, ic, ib)] = keys
    fields: dict[str, np.ndarray] = {}
    by_key = {run.key: run for run in runs}
    for run, result in iter_runs(list(runs) + ([image[1]] if image is not None else []), **run_options):
        fields[run.key] = result
        for (end, ic, ib), keys in list(pending.items()):
            if keys <= fields.keys():
                by_freq = _tl_by_freq(area, [by_key[key] for key in keys if key in by_key], fields)
                band_tl = band_tl_from_runs(area, area.classes[ic], area.bands[ib], by_freq)
                if end == "observer" and image is not None:
                    band_tl = with_image_rows(band_tl, image[0], fields[image[1].key], ic, ib)
                fill(end, ic, ib, band_tl)
                del pending[(end, ic, ib)]
        needed = set().union(*pending.values()) if pending else set()
        for key in list(fields):
            if key not in needed:
                del fields[key]


def needs_observer_tl(area: Area) -> bool:
    """Whether a flat grid of ``area`` holds ``tl_obs_db``: when a class has a ``depth_range_m``."""
    return any(cls.depth_range_m is not None for cls in area.classes)


def grid_size_bytes(area: Area) -> float:
    """Memory a grid build of ``area`` needs at its peak, bytes (an estimate).

    The float32 TL tables (from the class's depth, and from the observer's when a class has a
    ``depth_range_m``: class x band x depth x range) twice (built, then encoded for netCDF), and a
    few float64 / complex64 fields
    of depth x range per run in flight.
    """
    n_depth = math.ceil(area.water.depth_m / area.grid.depth_step_m) + 1
    n_range = round(area.grid.range_max_m / area.grid.range_step_m)
    cells = float(n_depth) * n_range
    tables = 2.0 if needs_observer_tl(area) else 1.0
    return 8.0 * tables * len(area.classes) * len(area.bands) * cells + 48.0 * cells


def expected_source_hash(area: Area, model: Model | str = Model.BELLHOP) -> str:
    """The ``source_hash`` a grid of ``area`` built now would have (reads the data files)."""
    model = Model(model)
    return grid_source_hash(area, model, find_bellhop().sha256 if model.runs_bellhop else None)


def build_flat_grid(area: Area, model: Model, *, workers: int, scheduler: str | None,
                    cache_dir: str | Path | None, progress: bool, stats: BuildStats) -> xr.Dataset:
    """The grid of an area without ``[origin]`` with BELLHOP or the Urick formula alone
    (``acoustics.builder.buildgrid.build_grid`` says what each parameter is)."""
    check_memory(grid_size_bytes(area), f"the grid of area {area.name}")
    depth = area.depth_m()
    # TL from the observer in the semicoherent mode: near-surface rows, and the 0 m row holding
    # the loss 1 m down (acoustics.surface)
    surface = needs_observer_tl(area) and area.propagation.mode is TlMode.SEMICOHERENT
    if surface:
        depth = with_surface_rows(depth)
    rng = area.grid.range_m()
    exe = find_bellhop() if model is Model.BELLHOP else None
    n_cls, n_band = len(area.classes), len(area.bands)
    tl = np.empty((n_cls, n_band, depth.size, rng.size), dtype=np.float32)
    # TL from the observer for the trackers that look for the target's depth: only where a class
    # says its depth is uncertain (the extra source depth costs a third more runs on ocean-deep)
    tl_obs = np.empty_like(tl) if needs_observer_tl(area) else None
    k = np.empty((n_cls, n_band, rng.size))
    k_urick, beta = urick_tables(area, rng)

    if model is Model.BELLHOP:
        rz = np.unique(np.concatenate([depth, [area.observer.depth_m], [SURFACE_ROW_M] if surface else []]))
        on_grid = np.searchsorted(rz, depth)
        obs_row = int(np.searchsorted(rz, area.observer.depth_m))
        surface_row = int(np.searchsorted(rz, SURFACE_ROW_M))
        source_depths = sorted({cls.depth_m for cls in area.classes}
                               | ({area.observer.depth_m} if tl_obs is not None else set()))
        runs = plan_runs(area, source_depths, receiver_depths=rz)
        # TL from the observer: the surface at the target's end of its near-surface rows
        image = plan_image_run(area, rz, lambda z: area.water.ssp.speed_at(z),
                               lambda spec: {"env": env_text(area, spec), **spec.side_files()},
                               title=f"tmakit {area.name}") if tl_obs is not None else None
        stats.runs = runs + ([image[1]] if image is not None else [])

        def fill(end: str, ic: int, ib: int, band_tl: np.ndarray) -> None:
            if end == "observer":
                tl_obs[ic, ib] = band_tl[on_grid]
                if surface:
                    tl_obs[ic, ib, 0] = band_tl[surface_row]
                return
            cls, band = area.classes[ic], area.bands[ib]
            tl[ic, ib] = band_tl[on_grid]
            k[ic, ib] = spectral_term_db(cls, band) - band_tl[obs_row]

        _assemble(area, runs, fill, observer_end=tl_obs is not None, image=image,
                  workers=workers, scheduler=scheduler,
                  cache_dir=Path(cache_dir) if cache_dir is not None else None, progress=progress,
                  exe=str(exe.path), stats=stats)
    else:
        for ib in range(len(area.bands)):
            tl[:, ib] = spherical_tl_db(rng, beta_db_per_km=beta[ib])[None, None, :]
        if tl_obs is not None:
            tl_obs[:] = tl  # spherical spreading does not depend on either end's depth
        k[:] = k_urick

    from acoustics.grid.dataset import flat_dataset  # xarray: imported beside the runs

    return flat_dataset(area, model, depth, rng, tl, k, k_urick, beta,
                        grid_source_hash(area, model, exe.sha256 if exe else None), exe.describe() if exe else None,
                        tl_obs=tl_obs)


def build_flat_ram_grid(area: Area, model: Model, *, workers: int, scheduler: str | None,
                    cache_dir: str | Path | None, progress: bool, stats: BuildStats) -> xr.Dataset:
    """The flat grid with RAM runs (``ram``, ``auto``): one RAM run per (class source depth,
    frequency), BELLHOP's share (``auto``) as usual, each band from ``modelchoice``."""
    depth = area.depth_m()
    rng = area.grid.range_m()
    prop = area.propagation
    plans = band_plans(area, model)
    ram_hz = ram_run_hz(plans)
    bh_hz = bellhop_run_hz(area, plans) if model.runs_bellhop else []
    exe = find_bellhop() if model.runs_bellhop else None
    rz = receiver_depths_m(area)
    on_grid = np.searchsorted(rz, depth)
    obs_row = int(np.searchsorted(rz, area.observer.depth_m))
    source_depths = sorted({cls.depth_m for cls in area.classes})
    ram_runs = {}
    for sd in source_depths:
        env = RamEnvironment.from_area(area, sd)
        ram_runs[sd] = [RamRun(env=env, freq_hz=f, depth_m=rz, range_m=rng, tl_max_db=prop.tl_max_db)
                        for f in ram_hz]
    check_model_memory(grid_size_bytes(area), [r for runs in ram_runs.values() for r in runs],
                       1 if scheduler else workers, f"the RAM grid of area {area.name}")
    bh_runs = plan_runs(area, receiver_depths=rz, balance=False, freqs_hz=bh_hz) if bh_hz else []
    stats.runs = bh_runs
    n_cls, n_band = len(area.classes), len(area.bands)
    tl = np.empty((n_cls, n_band, depth.size, rng.size), dtype=np.float32)
    k = np.empty((n_cls, n_band, rng.size))
    k_urick, beta = urick_tables(area, rng)

    def on_source(sd, ram_tl, bh_tl) -> None:
        for ic, cls in enumerate(area.classes):
            if cls.depth_m != sd:
                continue
            for ib, plan in enumerate(plans):
                band_tl = planned_band_tl_db(area, cls, plan, ram_tl, bh_tl)
                tl[ic, ib] = band_tl[on_grid]
                k[ic, ib] = spectral_term_db(cls, plan.band) - band_tl[obs_row]

    run_sources(area, source_depths, ram_runs, bh_runs, {run.key: (run.source_depth_m, run.freq_hz) for run in bh_runs},
                on_source, workers=workers, scheduler=scheduler,
                cache_dir=Path(cache_dir) if cache_dir is not None else None, progress=progress,
                exe=str(exe.path) if exe else None, stats=stats)
    from acoustics.grid.dataset import flat_dataset  # xarray: imported beside the runs

    ds = flat_dataset(area, model, depth, rng, tl, k, k_urick, beta,
                      grid_source_hash(area, model, exe.sha256 if exe else None), exe.describe() if exe else None)
    return with_ram_attrs(ds, model)
