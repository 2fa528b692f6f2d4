"""Bearing-dependent grids: N x 2D BELLHOP runs along radials from the origin.

docs/formats.md "Bearing-dependent grid". Every area with an ``[origin]`` gets
this grid. For each radial (``envdata.radials``) and run frequency, one BELLHOP run with the
range-dependent bottom (.bty) and sound speed ('Q' .ssp) of that radial, the source at the
observer's depth at the origin, and receivers on the grid's depth axis plus the class depths.
By reciprocity the run's TL from the observer to a point at depth z and range r along the
radial is the loss between that point and the observer; so

- ``tl_db(class, band, bearing, depth, range)`` is the band TL (the class's spectrum weighting
  the band, as in ``acoustics.builder.flat``) between the observer and a point at ``depth``
  (``fixed_end = "observer"``);
- ``k_db(class, band, bearing, range) = S - TL`` at the class's depth (eq. 12-13): K(r) for a
  target of the class at ``range`` along ``bearing`` from the observer;
- cells below the bottom and beyond land are NaN, and ``bottom_depth_m(bearing, range)`` is the
  water depth along each radial.

The runs of all radials go through the same executor as a flat grid's (threads or a Dask
cluster, a resume folder). Incoherent beams near the pressure-release surface are not quite
reciprocal (docs/sensitivity.md: up to 2.4 dB for sources at 6-8 m); that is the price of one
run per radial instead of one per target position.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from acoustics.bellhop.exe import find_bellhop
from acoustics.bellhop.radialfiles import radial_files
from acoustics.bellhop.shdfile import tl_from_pressure
from acoustics.builder.bandruns import (
    BuildStats,
    Model,
    band_tl_from_runs,
    field_run_frequencies_hz,
    freq_key,
    run_timeout_s,
    source_hash,
)
from acoustics.builder.imageruns import plan_image_run, with_image_rows
from acoustics.builder.modelchoice import (
    band_plans,
    bellhop_run_hz,
    model_settings,
    planned_band_tl_db,
    ram_run_hz,
    with_ram_attrs,
)
from acoustics.builder.modelruns import check_model_memory, run_sources
from acoustics.builder.plan import run_spec
from acoustics.builder.ramruns import RamRun
from acoustics.builder.runs import Run, iter_runs
from acoustics.kcurve import spectral_term_db
from acoustics.ram import RamEnvironment
from acoustics.surface import SURFACE_ROW_M, with_surface_rows
from acoustics.urick import urick_tables
from envdata.area import Area, TlMode
from envdata.datafiles import input_file_digests
from envdata.fieldchange import FieldChange
from envdata.limits import check_memory
from envdata.radials import Radial, area_radials

if TYPE_CHECKING:  # xarray is imported beside the runs (acoustics.builder.preload)
    import xarray as xr

#: Ray step when the area does not set ``[propagation] step_m``, m (bench/bench_radials.py:
#: converged to 0.1 dB median against a 5 m step on the built-in shelf-break area).
DEFAULT_STEP_M = 25.0
#: Rays leave the box this far beyond the last grid range, relative and m.
BOX_MARGIN = (1.01, 10.0)


def depth_axis_m(area: Area, radials: list[Radial]) -> np.ndarray:
    """0 to the deepest bottom on any radial (within the grid's ranges), every depth_step_m, and
    in the semicoherent mode the near-surface rows within the first step
    (``acoustics.surface.with_surface_rows``)."""
    r_max = area.grid.range_max_m
    deepest = max(float(np.max(rad.bottom_depth_m[(rad.range_m >= 0) & (rad.range_m <= r_max)]))
                  for rad in radials)
    step = area.grid.depth_step_m
    z = np.arange(0.0, deepest, step)
    z = z if z.size and z[-1] >= deepest - 1e-9 else np.append(z, deepest)
    return with_surface_rows(z) if area.propagation.mode is TlMode.SEMICOHERENT else z


def bottom_on_grid_m(area: Area, radial: Radial) -> np.ndarray:
    """Water depth of a radial at the grid's ranges, m; NaN beyond land."""
    rng = area.grid.range_m()
    bottom = np.interp(rng, radial.range_m, radial.bottom_depth_m)
    if radial.land_range_m is not None:
        bottom = np.where(rng > radial.land_range_m, np.nan, bottom)
    return bottom


def plan_radial_runs(area: Area, radials: list[Radial], receivers_m: np.ndarray, freqs_hz=None
                     ) -> tuple[list[Run], dict[str, tuple[int, float]]]:
    """The BELLHOP runs of every radial and run frequency (the bands', or ``freqs_hz``; one run a
    radial where one run makes a band, ``bandruns.shared_run_hz``), and each run's (radial,
    frequency)."""
    prop = area.propagation
    rng = area.grid.range_m()
    box_range_m = float(rng.max()) * BOX_MARGIN[0] + BOX_MARGIN[1]
    step_m = prop.step_m if prop.step_m is not None else DEFAULT_STEP_M
    freqs = field_run_frequencies_hz(area) if freqs_hz is None else \
        list(dict.fromkeys(freq_key(f) for f in freqs_hz))
    runs, where = [], {}
    for j, radial in enumerate(radials):
        for f in freqs:
            spec = run_spec(area, title=f"tmakit {area.name} bearing={radial.bearing_deg:g} f={f:.3f} Hz",
                            freq_hz=f, source_depths_m=(area.observer.depth_m,),
                            receiver_depths_m=receivers_m, ranges_m=rng)
            files = radial_files(area, radial, spec, step_m=step_m, box_range_m=box_range_m)
            run = Run(env=files["env"], files=(("bty", files["bty"]), ("ssp", files["ssp"])),
                      freq_hz=f, source_depth_m=area.observer.depth_m, n_beams=prop.n_beams,
                      timeout_s=run_timeout_s(area, prop.n_beams, receivers_m.size * rng.size))
            runs.append(run)
            where[run.key] = (j, f)
    return runs, where


def origin_speed_of(radial: Radial):
    """The sound speed at depths at the radial's origin column, m/s (the observer's water)."""
    col = int(np.argmin(np.abs(np.asarray(radial.ssp_range_m, dtype=float))))
    z, c = np.asarray(radial.ssp_depth_m, dtype=float), np.asarray(radial.speed_mps, dtype=float)[:, col]
    return lambda depth: np.interp(np.asarray(depth, dtype=float), z, c)


def plan_radial_image_runs(area: Area, radials: list[Radial], receivers_m: np.ndarray
                           ) -> tuple[list[Run], dict[str, tuple[int, np.ndarray]]]:
    """The arrivals run of every radial that puts the surface at the target's end
    (``acoustics.builder.imageruns``), and each run's (radial, receiver rows)."""
    prop = area.propagation
    rng = area.grid.range_m()
    box_range_m = float(rng.max()) * BOX_MARGIN[0] + BOX_MARGIN[1]
    step_m = prop.step_m if prop.step_m is not None else DEFAULT_STEP_M
    runs, where = [], {}
    for j, radial in enumerate(radials):
        def make_files(spec, radial=radial):
            return radial_files(area, radial, spec, step_m=step_m, box_range_m=box_range_m)

        planned = plan_image_run(area, receivers_m, origin_speed_of(radial), make_files,
                                 title=f"tmakit {area.name} bearing={radial.bearing_deg:g}")
        if planned is not None:
            rows, run = planned
            runs.append(run)
            where[run.key] = (j, rows)
    return runs, where


class _RadialRuns:
    """Collects the field runs and the arrivals run of each radial as they finish; a radial is
    complete when all are in. ``band_tl(ic, ib)`` is then its band TL (receivers x range), the
    near-surface rows from the arrivals run (the surface at the target's end)."""

    def __init__(self, area: Area, field_where: dict, image_where: dict):
        self.area = area
        self.field_where, self.image_where = field_where, image_where
        self.n_freq = len({f for _, f in field_where.values()})
        self.has_image = {j for j, _ in image_where.values()}
        self.fields: dict[int, dict[float, np.ndarray]] = {}
        self.images: dict[int, tuple[np.ndarray, np.ndarray]] = {}

    def add(self, run: Run, result: np.ndarray) -> int | None:
        """Take one finished run; the radial's index when that completes it."""
        if run.image is not None:
            j, rows = self.image_where[run.key]
            self.images[j] = (rows, result)
        else:
            j, f = self.field_where[run.key]
            self.fields.setdefault(j, {})[f] = tl_from_pressure(result, self.area.propagation.tl_max_db)
        done = len(self.fields.get(j, {})) == self.n_freq and (j in self.images or j not in self.has_image)
        return j if done else None

    def pop(self, j: int):
        """The completed radial's band TL function, its runs dropped."""
        by_freq, image = self.fields.pop(j), self.images.pop(j, None)
        area = self.area

        def band_tl(ic: int, ib: int) -> np.ndarray:
            tl = band_tl_from_runs(area, area.classes[ic], area.bands[ib], by_freq)
            return with_image_rows(tl, image[0], image[1], ic, ib) if image is not None else tl
        return band_tl


def radial_grid_bytes(area: Area, n_depth: int) -> float:
    """Memory a bearing-dependent build needs at its peak, bytes (an estimate).

    The float32 TL table (class x band x bearing x depth x range) twice (built, then encoded
    for netCDF), and per radial in flight a few float64 fields of depth x range per frequency.
    """
    n_range = area.grid.range_m().size
    n_bearing = len(area.bearings.bearing_deg)
    cells = float(n_depth) * n_range
    return 8.0 * len(area.classes) * len(area.bands) * n_bearing * cells + 64.0 * len(area.bands) * cells


@dataclass(frozen=True, eq=False, kw_only=True)
class RadialArrays:
    """The tables of a bearing-dependent area as arrays: what a grid file and an atlas's table
    are both made of (`build_radial_grid` wraps them in the grid dataset, an atlas writes them
    into its store's chunks).

    Attributes
    ----------
    bearing_deg : ndarray, shape (N,)
    depth_m : ndarray, shape (D,)
    range_m : ndarray, shape (R,)
    tl_db : ndarray, shape (C, M, N, D, R), float32
        Band TL between the observer and a point at depth, dB; NaN below the bottom and beyond land.
    k_db : ndarray, shape (C, M, N, R)
        K(r) of a target of the class along each radial, dB.
    bottom_depth_m : ndarray, shape (N, R)
        Water depth along each radial, m; NaN beyond land.
    k_urick_db : ndarray, shape (C, M, R)
    beta_db_per_km : ndarray, shape (M,)
    exe_info : dict or None
        The BELLHOP executable that ran (``BellhopExe.describe``), None without BELLHOP.
    """

    bearing_deg: np.ndarray
    depth_m: np.ndarray
    range_m: np.ndarray
    tl_db: np.ndarray
    k_db: np.ndarray
    bottom_depth_m: np.ndarray
    k_urick_db: np.ndarray
    beta_db_per_km: np.ndarray
    exe_info: dict | None


def build_radial_grid(area: Area, *, model: Model | str = Model.BELLHOP, workers: int = 1,
                      scheduler: str | None = None, cache_dir: str | Path | None = None,
                      progress: bool = False, stats: BuildStats | None = None,
                      radials: list[Radial] | None = None, depth_m: np.ndarray | None = None,
                      inputs: dict | None = None, change: FieldChange | None = None,
                      exe: str | None = None) -> xr.Dataset:
    """The bearing-dependent grid dataset (docs/formats.md) for an area with ``[origin]``.

    Parameters as ``acoustics.build_grid``, which calls this for such an area; ``change`` (a
    sensitivity member's change to the data the area reads, ``envdata.fieldchange``) is applied
    before the radials are cut; ``exe`` names the BELLHOP executable (default ``find_bellhop``);
    ``radials`` and ``depth_m`` as for `radial_tables`; and

    inputs : dict, optional
        The data files' digests (``input_file_digests(area.water)``), already computed.
    """
    model = Model(model)
    inputs = inputs if inputs is not None else input_file_digests(area.water)
    exe_sha = find_bellhop().sha256 if model.runs_bellhop else None
    digest = source_hash(area, model, exe_sha, inputs, model_settings(model))
    arrays = radial_tables(area, model=model, workers=workers, scheduler=scheduler, cache_dir=cache_dir,
                           progress=progress, stats=stats, radials=radials, depth_m=depth_m, change=change,
                           exe=exe)
    from acoustics.grid.dataset import radial_dataset  # xarray: imported beside the runs

    ds = radial_dataset(area, model, digest, arrays.exe_info, bearing_deg=arrays.bearing_deg, depth_m=arrays.depth_m,
                        range_m=arrays.range_m, tl_db=arrays.tl_db, k_db=arrays.k_db, k_urick_db=arrays.k_urick_db,
                        bottom_depth_m=arrays.bottom_depth_m, beta_db_per_km=arrays.beta_db_per_km,
                        ray_step_m=area.propagation.step_m if area.propagation.step_m is not None else DEFAULT_STEP_M,
                        input_files=inputs)
    return with_ram_attrs(ds, model) if model.runs_ram else ds


def radial_tables(area: Area, *, model: Model | str = Model.BELLHOP, workers: int = 1,
                  scheduler: str | None = None, cache_dir: str | Path | None = None,
                  progress: bool = False, stats: BuildStats | None = None,
                  radials: list[Radial] | None = None, depth_m: np.ndarray | None = None,
                  change: FieldChange | None = None, exe: str | None = None) -> RadialArrays:
    """The tables of a bearing-dependent area, as arrays: the one radial-table builder of grid
    files (`build_radial_grid`) and atlases (``acoustics.builder.atlas``, one call per table).

    Parameters as `build_radial_grid`, and

    radials : list of Radial, optional
        The area's radials, already sampled (default: ``area_radials(area)``).
    depth_m : ndarray, optional
        The TL depth axis, m (default: ``depth_axis_m``, 0 to the deepest bottom every
        ``[grid] depth_step_m``).
    """
    model = Model(model)
    exe_path = exe
    stats = stats if stats is not None else BuildStats()
    exe = find_bellhop() if model.runs_bellhop else None
    radials = radials if radials is not None else area_radials(area, progress=progress, change=change)
    depth = np.asarray(depth_m, dtype=float) if depth_m is not None else depth_axis_m(area, radials)
    if not model.runs_ram:
        check_memory(radial_grid_bytes(area, depth.size), f"the grid of area {area.name}")
    rng = area.grid.range_m()
    class_depths = sorted({c.depth_m for c in area.classes})
    surface_depth = [SURFACE_ROW_M] if area.propagation.mode is TlMode.SEMICOHERENT and depth[0] == 0.0 else []
    receivers = np.unique(np.concatenate([depth, class_depths, surface_depth]))
    on_grid = np.searchsorted(receivers, depth)
    surface_row = int(np.searchsorted(receivers, SURFACE_ROW_M)) if surface_depth else None
    class_row = {z: int(np.searchsorted(receivers, z)) for z in class_depths}
    n_c, n_b, n_n = len(area.classes), len(area.bands), len(radials)
    bottom = np.stack([bottom_on_grid_m(area, rad) for rad in radials])       # (N, R)
    tl = np.full((n_c, n_b, n_n, depth.size, rng.size), np.nan, dtype=np.float32)
    k = np.full((n_c, n_b, n_n, rng.size), np.nan)
    prop = area.propagation
    k_urick, beta = urick_tables(area, rng)

    def fill(j: int, band_tl_db) -> None:
        """Radial ``j``'s cells from ``band_tl_db(ic, ib)``, the band TL on the receivers."""
        # below the bottom, and beyond land (NaN bottom), the grid has no value
        below = (depth[:, None] > bottom[j][None, :] + 1e-6) | ~np.isfinite(bottom[j])[None, :]
        for ic, cls in enumerate(area.classes):
            for ib, band in enumerate(area.bands):
                band_tl = band_tl_db(ic, ib)  # (receivers, R)
                tl[ic, ib, j] = np.where(below, np.nan, band_tl[on_grid])
                if surface_row is not None:  # the 0 m row: the loss 1 m down (SURFACE_ROW_M)
                    tl[ic, ib, j, 0] = np.where(below[0], np.nan, band_tl[surface_row])
                kk = spectral_term_db(cls, band) - band_tl[class_row[cls.depth_m]]
                # a target deeper than the water there, or beyond land, has no K
                k[ic, ib, j] = np.where(cls.depth_m < bottom[j], kk, np.nan)

    if model.runs_ram:
        plans = band_plans(area, model)
        bh_hz = bellhop_run_hz(area, plans) if model.runs_bellhop else []
        ram_runs = {j: [RamRun(env=RamEnvironment.from_radial(area, rad, area.observer.depth_m), freq_hz=f,
                               depth_m=receivers, range_m=rng, tl_max_db=prop.tl_max_db)
                        for f in ram_run_hz(plans)] for j, rad in enumerate(radials)}
        check_model_memory(radial_grid_bytes(area, depth.size), [r for runs in ram_runs.values() for r in runs],
                           1 if scheduler else workers, f"the RAM grid of area {area.name}")
        runs, where = plan_radial_runs(area, radials, receivers, freqs_hz=bh_hz) if bh_hz else ([], {})
        # BELLHOP's bands from the observer take their near-surface rows from the arrivals runs
        image_runs, image_where = plan_radial_image_runs(area, radials, receivers) if bh_hz else ([], {})
        stats.runs = runs + image_runs
        images = {}
        if image_runs:
            for run, result in iter_runs(image_runs, workers=workers, scheduler=scheduler,
                                         cache_dir=Path(cache_dir) if cache_dir is not None else None,
                                         progress=progress, exe=str(exe.path), stats=stats):
                images[image_where[run.key][0]] = (image_where[run.key][1], result)

        def on_source(j, ram_tl, bh_tl) -> None:
            def band_tl(ic, ib):
                tl = planned_band_tl_db(area, area.classes[ic], plans[ib], ram_tl, bh_tl)
                if plans[ib].bellhop_only and j in images:
                    tl = with_image_rows(tl, images[j][0], images[j][1], ic, ib)
                return tl
            fill(j, band_tl)

        run_sources(area, range(n_n), ram_runs, runs, where, on_source, workers=workers, scheduler=scheduler,
                    cache_dir=Path(cache_dir) if cache_dir is not None else None, progress=progress,
                    exe=str(exe.path) if exe else None, stats=stats)
    elif model is Model.BELLHOP:
        runs, where = plan_radial_runs(area, radials, receivers)
        image_runs, image_where = plan_radial_image_runs(area, radials, receivers)
        stats.runs = runs + image_runs
        collect = _RadialRuns(area, where, image_where)
        for run, result in iter_runs(runs + image_runs, workers=workers, scheduler=scheduler,
                                     cache_dir=Path(cache_dir) if cache_dir is not None else None,
                                     progress=progress, exe=exe_path or str(exe.path), stats=stats):
            j = collect.add(run, result)
            if j is not None:
                band_tl = collect.pop(j)
                fill(j, band_tl)
    else:  # Urick: spherical spreading and absorption, the same along every radial
        from acoustics.urick import spherical_tl_db

        for ib in range(n_b):
            sph = spherical_tl_db(rng, beta_db_per_km=beta[ib])
            for j in range(n_n):
                below = (depth[:, None] > bottom[j][None, :]) | ~np.isfinite(bottom[j])[None, :]
                tl[:, ib, j] = np.where(below, np.nan, sph[None, :])[None]
                k[:, ib, j] = np.where(np.isfinite(bottom[j]), k_urick[:, ib], np.nan)
    return RadialArrays(bearing_deg=np.array([rad.bearing_deg for rad in radials]), depth_m=depth, range_m=rng,
                        tl_db=tl, k_db=k, bottom_depth_m=bottom, k_urick_db=k_urick, beta_db_per_km=beta,
                        exe_info=exe.describe() if exe else None)


def radial_k_db(area: Area, *, change: FieldChange | None = None, workers: int = 1,
                exe: str | None = None, stats: BuildStats | None = None,
                radials: list[Radial] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """K alone of a bearing-dependent area: ``k_db(class, band, bearing, range)`` and
    ``bottom_depth_m(bearing, range)``, as `build_radial_grid` computes them.

    The same runs (the source at the observer, reciprocity) with receivers at the class depths
    only, so no TL table is kept: what a sensitivity member needs. NaN beyond land and where the
    class is deeper than the water. ``change`` and ``radials`` as for `build_radial_grid`.
    """
    stats = stats if stats is not None else BuildStats()
    exe = exe if exe is not None else str(find_bellhop().path)
    if radials is None:
        radials = area_radials(area, change=change)
    rng = area.grid.range_m()
    receivers = np.array(sorted({c.depth_m for c in area.classes}))
    row = {z: i for i, z in enumerate(receivers)}
    bottom = np.stack([bottom_on_grid_m(area, rad) for rad in radials])
    k = np.full((len(area.classes), len(area.bands), len(radials), rng.size), np.nan)
    runs, where = plan_radial_runs(area, radials, receivers)
    image_runs, image_where = plan_radial_image_runs(area, radials, receivers)
    stats.runs = runs + image_runs
    collect = _RadialRuns(area, where, image_where)
    for run, result in iter_runs(runs + image_runs, workers=workers, exe=exe, stats=stats):
        j = collect.add(run, result)
        if j is None:
            continue
        band_tl = collect.pop(j)
        for ic, cls in enumerate(area.classes):
            for ib, band in enumerate(area.bands):
                kk = spectral_term_db(cls, band) - band_tl(ic, ib)[row[cls.depth_m]]
                k[ic, ib, j] = np.where(cls.depth_m < bottom[j], kk, np.nan)
    return k, bottom
