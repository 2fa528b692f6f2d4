"""Atlases: the bearing-dependent grid of every observer position and month, in one Zarr store.

README "Atlases". The plan (this process): read the area's ``[atlas]``, the box of bathymetry
every table's radials cross (once), and each month's climatology box (once per month); leave
out positions on land or shallower than the observer; write the store's template
(``acoustics.grid.atlas.format``). Then one task per (month, origin) table runs on local threads
or Dask workers (``acoustics.builder.executor.run_tasks``; the boxes reach each worker once):
it samples its radials from the boxes, builds the tables of the area with ``[origin]`` at that
position with the radial-table builder of every bearing-dependent grid
(``acoustics.builder.radial.radial_tables``: arrays, no dataset), and writes them into its own
chunks of the store, then its ``done`` flag and the hash of its inputs. Nothing gathers the
atlas in one process. A rebuild recomputes the tables not done, whose hash changed, or whose
chunks are missing or fail their checksum.
"""

from __future__ import annotations

import hashlib
import json
import shutil
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from acoustics.bellhop.exe import find_bellhop
from acoustics.builder.bandruns import BuildStats, Model, source_hash
from acoustics.builder.executor import TaskStats, run_tasks
from acoustics.builder.radial import DEFAULT_STEP_M, depth_axis_m, radial_tables
from acoustics.grid.atlas.format import (
    AtlasFileError,
    check_format,
    clear_done,
    is_atlas_store,
    read_attrs,
    remove_store,
    set_done,
    store_template,
    table_hash_u64,
    table_readable,
    write_table,
    write_template,
)
from acoustics.grid.formats import ATLAS_FORMAT
from acoustics.surface import with_surface_rows
from envdata.area import Area, TlMode
from envdata.atlasarea import LeftOut, area_for_month, radial_reach, screen_positions, table_area
from envdata.datafiles import input_file_digests
from envdata.errors import AreaError, InputError
from envdata.limits import TooLargeError, check_memory
from envdata.radials import area_radials
from envdata.watersources import (
    LoadedBathymetry,
    WaterSources,
    load_bathymetry_box,
    load_climatology_box,
    single_month,
)

#: Bytes of the store per raw float32 byte that the disk must have free before a build (the
#: tables compress, but a shadowless deep table may not).
DISK_MARGIN = 1.1


@dataclass(frozen=True, eq=False)
class TableContext:
    """What every table task needs; sent to each Dask worker once."""

    store: str
    area: Area
    model: str
    months: tuple[int, ...]
    lat_deg: np.ndarray
    lon_deg: np.ndarray
    depth_m: np.ndarray  # the atlas's depth axis
    own_depth_axis: bool  # True: each table on the grid's own axis (no [atlas] depth setting)
    sources: tuple[WaterSources, ...]  # per month
    hashes: np.ndarray  # (months, origins) uint64


@dataclass(frozen=True, eq=False)
class AtlasPlan:
    """The atlas of an area as planned: positions kept and left out, axes, and each table's hash."""

    area: Area
    model: Model
    months: tuple[int, ...]
    lat_deg: np.ndarray
    lon_deg: np.ndarray
    row_col: np.ndarray  # (origins, 2) lattice row and column, -1 for listed positions
    left_out: list[LeftOut]
    depth_m: np.ndarray
    range_m: np.ndarray
    bearing_deg: np.ndarray
    sources: tuple[WaterSources, ...]
    inputs: tuple[dict, ...]
    hashes: np.ndarray  # (months, origins) uint64
    digest: str
    exe_info: dict | None

    @property
    def n_tables(self) -> int:
        return len(self.months) * self.lat_deg.size

    def raw_bytes(self) -> float:
        """The store's tables uncompressed (float32 TL, float64 K), bytes."""
        a = self.area
        per = len(a.classes) * len(a.bands) * self.bearing_deg.size * self.range_m.size
        return self.n_tables * per * (4.0 * self.depth_m.size + 8.0)


def atlas_depth_axis_m(area: Area, deepest_m: float) -> np.ndarray:
    """The atlas's depth axis: ``[atlas] depth_m``, else 0 to ``deepest_m`` every ``[atlas]
    depth_step_m`` (else ``[grid] depth_step_m``, the grids' own axis), m."""
    if area.atlas.depth_m is not None:
        return np.asarray(area.atlas.depth_m, dtype=float)
    step = area.atlas.depth_step_m if area.atlas.depth_step_m is not None else area.grid.depth_step_m
    z = np.arange(0.0, deepest_m, step)
    z = z if z.size and z[-1] >= deepest_m - 1e-9 else np.append(z, deepest_m)
    # the near-surface rows of the grids' own axes (acoustics.builder.radial.depth_axis_m)
    return with_surface_rows(z) if area.propagation.mode is TlMode.SEMICOHERENT else z


def plan_atlas(area: Area, model: Model | str = Model.BELLHOP) -> AtlasPlan:
    """Plan the atlas of an area: read the data files once, screen the positions, hash the tables.

    Raises
    ------
    AreaError
        No ``[atlas]``; no position left in the water; several months over a climatology with
        one time step; a data file that does not cover the radials.
    """
    model = Model(model)
    if area.atlas is None:
        raise AreaError(f"area {area.name!r}: has no [atlas] (positions and months) to build an atlas of")
    months = area.atlas_months
    if len(months) > 1 and single_month(area):
        raise AreaError(f"[atlas] months: {list(months)}, but the climatology "
                        f"{area.water.climatology.temperature.path!r} holds one time step (one month); "
                        f"give a climatology with 12 (WOA's monthly files joined along time)")
    lat, lon, row_col = area.atlas.all_positions()
    reach_lat, reach_lon = radial_reach(area, lat, lon)
    bathy = load_bathymetry_box(area, reach_lat, reach_lon)
    keep, left_out = screen_positions(area, lat, lon, bathy)
    if not keep.any():
        raise AreaError(f"[atlas]: every one of the {lat.size} positions is left out ({left_out[0].reason} "
                        f"at {left_out[0].lat_deg:.4f} N {left_out[0].lon_deg:.4f} E, ...)")
    lat, lon, row_col = lat[keep], lon[keep], row_col[keep]
    reach_lat, reach_lon = radial_reach(area, lat, lon)
    sources, inputs = [], []
    for month in months:
        area_m = area_for_month(area, month)
        sources.append(WaterSources(bathymetry=bathy, climatology=load_climatology_box(area_m, reach_lat,
                                                                                       reach_lon)))
        inputs.append(input_file_digests(area_m.water))
    deepest = _deepest_m(area, bathy)
    depth = atlas_depth_axis_m(area, deepest)
    exe = find_bellhop() if model is Model.BELLHOP else None
    exe_sha = exe.sha256 if exe else None
    depth_key = "grid" if area.atlas.depth_m is None and area.atlas.depth_step_m is None else depth.tolist()
    hashes = np.zeros((len(months), lat.size), dtype=np.uint64)
    for m, month in enumerate(months):
        for o in range(lat.size):
            grid_hash = source_hash(table_area(area, month, lat[o], lon[o]), model, exe_sha, inputs[m])
            payload = json.dumps({"grid": grid_hash, "depth": depth_key, "atlas_format": ATLAS_FORMAT})
            hashes[m, o] = table_hash_u64(hashlib.sha256(payload.encode()).hexdigest())
    digest = hashlib.sha256(json.dumps({"area": area.to_dict(), "tables": hashes.tolist(),
                                        "depth": depth.tolist()}).encode()).hexdigest()
    return AtlasPlan(area=area, model=model, months=tuple(months), lat_deg=lat, lon_deg=lon, row_col=row_col,
                     left_out=left_out, depth_m=depth, range_m=area.grid.range_m(),
                     bearing_deg=np.asarray(area.bearings.bearing_deg, dtype=float), sources=tuple(sources),
                     inputs=tuple(inputs), hashes=hashes, digest=digest,
                     exe_info=exe.describe() if exe else None)


def _deepest_m(area: Area, bathy: LoadedBathymetry | None) -> float:
    """The deepest water any table can reach: the deepest cell of the box read, m."""
    if bathy is None:
        return float(area.water.depth_m)
    elevation = bathy.grid.elevation_m
    return float(max(-np.nanmin(elevation), area.observer.depth_m))


def compute_table(item: tuple[int, int], context: TableContext) -> dict:
    """One table: its radials from the boxes, its grid, written into its own chunks of the store."""
    m, o = item
    start = time.perf_counter()
    area_t = table_area(context.area, context.months[m], context.lat_deg[o], context.lon_deg[o])
    radials = area_radials(area_t, sources=context.sources[m])
    common = context.depth_m
    if context.own_depth_axis:
        own = depth_axis_m(area_t, radials)  # exactly the grid's axis; all but its last depth are common
    else:
        deepest = float(depth_axis_m(area_t, radials)[-1])
        own = common[common <= deepest + 1e-9]
        own = own if own.size else common[:1]
    stats = BuildStats()
    arrays = radial_tables(area_t, model=context.model, workers=1, radials=radials, depth_m=own, stats=stats)
    at = np.searchsorted(common, own)
    on_axis = (at < common.size) & (common[np.minimum(at, common.size - 1)] == own)
    tl_own = arrays.tl_db
    tl = np.full(tl_own.shape[:3] + (common.size,) + tl_own.shape[4:], np.nan, dtype=np.float32)
    tl[:, :, :, at[on_axis], :] = tl_own[:, :, :, on_axis, :]
    write_table(context.store, m, o, tl, arrays.k_db, arrays.bottom_depth_m if m == 0 else None)
    set_done(context.store, m, o, int(context.hashes[m, o]))
    return {"month": int(context.months[m]), "origin": int(o), "runs": len(stats.runs),
            "bellhop_seconds": float(stats.bellhop_seconds), "seconds": time.perf_counter() - start}


def _template(plan: AtlasPlan, store: Path) -> None:
    """Write the store's template: its format's (``acoustics.grid.atlas.format.store_template``)
    for the plan."""
    prop = plan.area.propagation
    write_template(store, store_template(
        plan.area, months=plan.months, lat_deg=plan.lat_deg, lon_deg=plan.lon_deg, row_col=plan.row_col,
        bearing_deg=plan.bearing_deg, depth_m=plan.depth_m, range_m=plan.range_m, model=plan.model,
        digest=plan.digest, exe_info=plan.exe_info, left_out=plan.left_out, inputs=plan.inputs,
        ray_step_m=float(prop.step_m if prop.step_m is not None else DEFAULT_STEP_M)))


def _differences(store: Path, plan: AtlasPlan) -> str | None:
    """What differs between an existing atlas and the plan's axes (None: nothing)."""
    import xarray as xr

    attrs = read_attrs(store)
    if attrs.get("area") != plan.area.name:
        return f"area {attrs.get('area')!r}, not {plan.area.name!r}"
    with xr.open_zarr(store, consolidated=False, zarr_format=3) as ds:
        wanted = {"month": np.asarray(plan.months), "origin_lat_deg": plan.lat_deg,
                  "origin_lon_deg": plan.lon_deg, "bearing": plan.bearing_deg, "depth": plan.depth_m,
                  "range": plan.range_m}
        for name, values in wanted.items():
            have = np.asarray(ds[name].values) if name in ds.variables else None
            if have is None or have.shape != values.shape or not np.allclose(have, values, rtol=0, atol=1e-9):
                n = "none" if have is None else have.size
                return f"its {name} ({n} values) differs from the area's ({values.size} values)"
        for name, items in (("class", plan.area.classes), ("band", plan.area.bands)):
            labels = json.loads(ds[name].attrs.get("labels", "[]"))
            if labels != [x.name for x in items]:
                return f"its {name} names {labels} differ from the area's {[x.name for x in items]}"
    return None


def build_atlas_file(area: Area, out: str | Path, *, model: Model | str = Model.BELLHOP, workers: int = 1,
                     scheduler: str | None = None, force: bool = False, progress: bool = False) -> dict:
    """Build (or bring up to date) the atlas store of an area.

    Parameters
    ----------
    area : Area
        An area with ``[origin]``, ``[bearings]`` and ``[atlas]``.
    out : path
        The Zarr store (a folder) to write.
    model, workers, scheduler, progress
        As for ``acoustics.builder.gridfile.build_grid_file``; a task is one table.
    force : bool
        Replace ``out`` whatever it is (another atlas, another area, not tmakit's), and recompute
        every table.

    Returns
    -------
    dict
        ``file``, ``area``, ``tables``, ``tables_done`` (reused), ``tables_built``, ``positions``,
        ``left_out``, ``runs``, ``bellhop_seconds``, ``wall_seconds``, ``dims``.

    Raises
    ------
    AtlasFileError
        ``out`` exists and is not a tmakit atlas, or is one of another format or area (naming what
        differs), and ``force`` is not set.
    TooLargeError
        The store would not fit on the disk, or one table in memory.
    """
    if scheduler is None and workers < 1:
        raise InputError(f"--workers: must be >= 1, got {workers}")
    start = time.perf_counter()
    out = Path(out)
    if out.exists() and not force:
        if not is_atlas_store(out):
            raise AtlasFileError(f"{out}: exists and is not a tmakit atlas; not replaced (build with force to "
                                 f"replace it)")
        check_format(out, read_attrs(out))
    plan = plan_atlas(area, model)
    _check_size(plan, out)
    reuse = out.exists() and not force
    if reuse:
        why = _differences(out, plan)
        if why is not None:
            raise AtlasFileError(f"{out}: an atlas of other axes or another area: {why}; not replaced (build "
                                 f"with force to replace it)")
    todo = _tables_to_build(out, plan) if reuse else None
    if todo is None:
        if out.exists():
            remove_store(out)
        _template(plan, out)
        todo = [(m, o) for m in range(len(plan.months)) for o in range(plan.lat_deg.size)]
    else:
        clear_done(out, todo)
        _update_attrs(out, plan)
    context = TableContext(store=str(out.resolve()), area=plan.area, model=str(plan.model), months=plan.months,
                           lat_deg=plan.lat_deg, lon_deg=plan.lon_deg, depth_m=plan.depth_m,
                           own_depth_axis=area.atlas.depth_m is None and area.atlas.depth_step_m is None,
                           sources=plan.sources, hashes=plan.hashes)
    # the months of one position one after another; positions interleaved longest first is moot:
    # tables of one area cost about the same
    stats = TaskStats()
    runs = 0
    bellhop_s = 0.0
    for done in run_tasks(compute_table, todo, key=lambda it: f"table-m{it[0]}-o{it[1]}", workers=workers,
                          scheduler=scheduler, progress=progress, desc=f"atlas {area.name}", unit="table",
                          stats=stats, context=context):
        runs += done.result["runs"]
        bellhop_s += done.result["bellhop_seconds"]
    return {"file": str(out), "area": area.name, "model": str(plan.model), "tables": plan.n_tables,
            "tables_built": len(todo), "tables_reused": plan.n_tables - len(todo),
            "positions": int(plan.lat_deg.size),
            "left_out": [{"lat_deg": p.lat_deg, "lon_deg": p.lon_deg, "reason": p.reason} for p in plan.left_out],
            "months": list(plan.months), "runs": runs, "bellhop_seconds": round(bellhop_s, 3),
            "workers": stats.workers, "wall_seconds": round(time.perf_counter() - start, 3),
            "raw_bytes": plan.raw_bytes(),
            "dims": {"month": len(plan.months), "origin": int(plan.lat_deg.size), "class": len(area.classes),
                     "band": len(area.bands), "bearing": int(plan.bearing_deg.size),
                     "depth": int(plan.depth_m.size), "range": int(plan.range_m.size)}}


def _check_size(plan: AtlasPlan, out: Path) -> None:
    """Refuse, before any work, an atlas the disk cannot hold or a table memory cannot."""
    raw = plan.raw_bytes()
    per_table = raw / plan.n_tables
    check_memory(4.0 * per_table, f"one table of the atlas of area {plan.area.name}")
    probe = out.parent if out.parent.exists() else Path(".")
    free = shutil.disk_usage(probe).free
    if not raw * DISK_MARGIN <= free:
        raise TooLargeError(f"{out}: the atlas of area {plan.area.name} ({plan.n_tables} tables, "
                            f"{plan.lat_deg.size} positions x {len(plan.months)} months) is {raw / 2**30:.3g} GiB "
                            f"uncompressed, more than the {free / 2**30:.3g} GiB free on {probe}")


def _tables_to_build(out: Path, plan: AtlasPlan) -> list[tuple[int, int]] | None:
    """The tables of an existing atlas that need computing: not done, of another hash, or with a
    chunk missing or damaged. None: the store cannot be read as an atlas (rebuilt whole)."""
    import zarr

    try:
        group = zarr.open_group(str(out), mode="r", zarr_format=3)
        done = np.asarray(group["done"][...])
        hashes = np.asarray(group["table_hash"][...])
    except Exception:  # noqa: BLE001 - a damaged flag chunk: the store is rebuilt whole
        return None
    todo = []
    for m in range(len(plan.months)):
        for o in range(plan.lat_deg.size):
            ok = (done[m, o] == 1 and hashes[m, o] == plan.hashes[m, o]
                  and table_readable(out, group, m, o, with_bottom=m == 0))
            if not ok:
                todo.append((m, o))
    return todo


def _update_attrs(out: Path, plan: AtlasPlan) -> None:
    """The store's attributes for the plan (area_json, source_hash) before tables are rebuilt."""
    import zarr

    group = zarr.open_group(str(out), mode="r+", zarr_format=3)
    from envdata.areafile import area_to_json

    group.attrs.update({"area_json": area_to_json(plan.area), "source_hash": plan.digest})
