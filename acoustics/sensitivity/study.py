"""Running a sensitivity study: the nominal area and every member as tasks, and the study dataset.

Each member is the area perturbed by ``acoustics.sensitivity.perturb`` with its own generator
``np.random.default_rng([seed, member])`` and its K(r) recomputed by BELLHOP
(``acoustics.sensitivity.members``). One task is one member (its BELLHOP runs inside), so the
result does not depend on how many workers there are or which worker ran what. The tasks run
on local threads or a Dask cluster (``acoustics.builder.executor``); finished members are kept in a
cache folder, so an interrupted study resumes without redoing them.
"""

from __future__ import annotations

import contextlib
import functools
import json
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from acoustics.bellhop.exe import find_bellhop
from acoustics.builder.executor import ResultCache, TaskStats, run_tasks
from acoustics.builder.radial import depth_axis_m
from acoustics.grid.dataset import now_iso
from acoustics.grid.formats import STUDY_FORMAT
from acoustics.sensitivity.members import MemberResult, compute_member, member_key, member_radials
from acoustics.sensitivity.perturbspec import Perturbation
from acoustics.sensitivity.spec import RECIPROCITY_MIN_DEPTH_M, StudySpec
from acoustics.version import TMAKIT_VERSION
from envdata.area import Area
from envdata.radials import area_radials


@dataclass
class StudyStats:
    """What a study did: members asked for and reused, workers, BELLHOP time, wall time."""

    members_total: int = 0
    members_reused: int = 0
    bellhop_seconds: float = 0.0  # BELLHOP process time of the members computed now (nominal included)
    wall_seconds: float = 0.0
    workers: int = 0


def member_cache(folder: str | Path) -> ResultCache[MemberResult]:
    """Finished members, ``nominal.npz`` and ``member-NNNNNN.npz``, in ``folder``."""
    return ResultCache(folder, encode=MemberResult.to_record, decode=MemberResult.from_record)


def run_study(area: Area, perturbations: Sequence[Perturbation], *, members: int, seed: int = 0,
              tl: bool = False, scheduler: str | None = None, workers: int = 1,
              cache_dir: str | Path | None = None, progress: bool = False,
              stats: StudyStats | None = None,
              reciprocity_min_depth_m: float = RECIPROCITY_MIN_DEPTH_M,
              on_result: Callable[[MemberResult], None] | None = None) -> xr.Dataset:
    """Run the ensemble and return the study dataset (``k_db(member, class, band, range)``, or
    ``k_db(member, class, band, bearing, range)`` for an area with ``[origin]``).

    Parameters
    ----------
    area : Area
        The nominal area.
    perturbations : sequence of Perturbation
        What is uncertain (``acoustics.sensitivity.perturb``); checked at +-4 sd before anything runs.
    members : int
        Ensemble size.
    seed : int
        Member m draws from ``np.random.default_rng([seed, m])``.
    tl : bool
        Full grid per member and keep ``tl_db(member, class, band, depth, range)``.
    scheduler : str, optional
        Address of a Dask distributed scheduler to run the members on.
    workers : int
        Members computed at once on local threads (ignored with ``scheduler``).
    cache_dir : path, optional
        Folder for finished members (resume); the caller removes it once the file is written.
    progress : bool
        Show a progress bar on stderr.
    stats : StudyStats, optional
        Filled with counts and timings.
    reciprocity_min_depth_m : float
        Classes at least this deep get K by reciprocity, m.
    on_result : callable, optional
        Called in the calling thread with each member's result as it arrives (not for reused
        ones), after it is saved in ``cache_dir``.
    """
    spec = StudySpec(area=area, perturbations=tuple(perturbations), members=members, seed=seed, tl=tl,
                     reciprocity_min_depth_m=reciprocity_min_depth_m)
    stats = stats if stats is not None else StudyStats()
    start = time.perf_counter()
    exe = find_bellhop()
    digest = spec.digest(exe.sha256)
    results: dict[int | None, MemberResult] = {}
    done = TaskStats()
    stats.members_total = members
    nominal_depth = None
    items: list = [None, *range(members)]
    fn = functools.partial(compute_member, spec, exe=str(exe.path))
    if area.is_bearing_dependent:
        # every member's radials are cut here, on this thread, before the members run on theirs:
        # the data files are netCDF, and netCDF-C and HDF5 are not thread-safe (a few hundredths
        # of a second per member against seconds of BELLHOP); a member found in the cache needs none
        cache = member_cache(cache_dir) if cache_dir is not None else None
        items = [(m, None if cache is not None and cache.load(member_key(m)) is not None else member_radials(spec, m))
                 for m in items]
        if tl:  # every member's TL on the nominal grid's depth axis
            nominal_depth = depth_axis_m(area, items[0][1] if items[0][1] is not None else area_radials(area))
        fn = functools.partial(_radial_task, spec, exe=str(exe.path), nominal_depth_m=nominal_depth)
    tasks = run_tasks(fn, items,
                      key=_item_key, workers=workers, scheduler=scheduler,
                      cache=member_cache(cache_dir) if cache_dir is not None else None,
                      progress=progress, desc="sensitivity members", unit="member", stats=done)
    with contextlib.closing(tasks):  # stops the pending members whatever happens here
        for item, result, reused in tasks:
            member = item[0] if isinstance(item, tuple) else item
            results[member] = result
            if reused:
                stats.members_reused += member is not None
            else:
                stats.bellhop_seconds += result.bellhop_seconds
                if on_result is not None:
                    on_result(result)
    stats.workers = done.workers
    ds = study_dataset(spec, results, digest, exe.describe())
    stats.wall_seconds = time.perf_counter() - start
    return ds


def _item_key(item) -> str:
    """A task's cache key: the member's (an item is a member, or a member and its radials)."""
    return member_key(item[0] if isinstance(item, tuple) else item)


def _radial_task(spec: StudySpec, item, exe: str, nominal_depth_m) -> MemberResult:
    member, radials = item
    return compute_member(spec, member, exe=exe, nominal_depth_m=nominal_depth_m, radials=radials)


def study_dataset(spec: StudySpec, results: dict[int | None, MemberResult], digest: str,
                  exe_info: dict) -> xr.Dataset:
    """The study dataset (docs/formats.md "Sensitivity study file") from the nominal result (key
    None) and every member's."""
    area = spec.area
    members = np.arange(spec.members)
    nominal = results[None]
    k = np.stack([results[int(m)].k_db for m in members])
    names = [n for p in sorted(spec.perturbations, key=lambda p: list(type(p.kind)).index(p.kind))
             for n in p.param_names()]
    coords = {
        "member": ("member", members, {"long_name": "ensemble member (seeded by [seed, member])"}),
        "class": ("class", np.array([c.name for c in area.classes], dtype=object),
                  {"long_name": "target class hypothesis"}),
        "band": ("band", np.array([b.name for b in area.bands], dtype=object), {"long_name": "frequency band"}),
        "range": ("range", area.grid.range_m(), {"units": "m", "long_name": "horizontal range from the source"}),
        "band_low_hz": ("band", np.array([b.low_hz for b in area.bands]), {"units": "Hz"}),
        "band_high_hz": ("band", np.array([b.high_hz for b in area.bands]), {"units": "Hz"}),
        "band_center_hz": ("band", np.array([b.center_hz for b in area.bands]), {"units": "Hz"}),
        "source_depth_m": ("class", np.array([c.depth_m for c in area.classes]),
                           {"units": "m", "long_name": "nominal radiating depth of the class", "positive": "down"}),
    }
    for name in names:
        coords[name] = ("member", np.array([results[int(m)].params[name] for m in members]),
                        {"long_name": f"perturbation parameter {name}", "units": _unit(name)})
    radial = area.is_bearing_dependent
    dims3 = ("class", "band", "bearing", "range") if radial else ("class", "band", "range")
    if radial:
        coords["bearing"] = ("bearing", np.asarray(area.bearings.bearing_deg, dtype=float),
                             {"units": "degree", "long_name": "bearing from the origin, clockwise from true north"})
        coords["range"] = ("range", area.grid.range_m(), {"units": "m", "long_name": "range from the origin "
                                                                                     "along the radial"})
    data_vars = {
        "k_db": (("member",) + dims3, k, {
            "units": "dB", "long_name": "transfer characteristic K(r) at the observer depth, perturbed member",
            "reference": "band level W = P0 + K(r) + H (Grinenkov & Mashoshin eq. 12)"}),
        "k_nominal_db": (dims3, nominal.k_db, {
            "units": "dB", "long_name": "transfer characteristic K(r) of the nominal area, same method"}),
    }
    if spec.tl:
        depth = nominal.depth_m if radial else area.depth_m()
        coords["depth"] = ("depth", depth, {"units": "m", "standard_name": "depth", "positive": "down",
                                            "axis": "Z", "long_name": "receiver depth"})
        tl_dims = ("class", "band", "bearing", "depth", "range") if radial else ("class", "band", "depth", "range")
        data_vars["tl_db"] = (("member",) + tl_dims,
                              np.stack([results[int(m)].tl_db for m in members]),
                              {"units": "dB", "long_name": "band transmission loss, perturbed member",
                               "reference": "1 m from the source",
                               "comment": "NaN below the member's bottom"})
        data_vars["tl_nominal_db"] = (tl_dims, nominal.tl_db,
                                      {"units": "dB", "long_name": "band transmission loss, nominal area",
                                       "reference": "1 m from the source"})
    method = ("grid build per member (direct for every class)" if spec.tl else
              f"reciprocity for classes at or below {spec.reciprocity_min_depth_m:g} m, direct above")
    if radial:
        method = ("bearing-dependent grid per member (N x 2D from the observer, reciprocity for every class)"
                  if spec.tl else "K per member along the radials (N x 2D from the observer, reciprocity "
                                  "for every class)")
    attrs = {
        "Conventions": "CF-1.8",
        "tmakit_format": STUDY_FORMAT,
        "title": f"tmakit environmental sensitivity study for area {area.name}",
        "institution": "tmakit",
        "source": f"tmakit {TMAKIT_VERSION}, model bellhop",
        "references": "Grinenkov & Mashoshin (2024) eqs. 12-13, 20; Porter, The BELLHOP manual (2011)",
        "comment": "dB quantities carry units 'dB' with their reference in the 'reference' attribute",
        "area": area.name,
        "model": "bellhop",
        "observer_depth_m": float(area.observer.depth_m),
        "seed": int(spec.seed),
        "members": int(spec.members),
        "perturbations": json.dumps([p.to_dict() for p in spec.perturbations]),
        "k_method": method,
        "reciprocity_min_depth_m": float(spec.reciprocity_min_depth_m),
        "bellhop_version": exe_info["version"],
        "bellhop_sha256": exe_info["sha256"],
        "created": now_iso(),
        "source_hash": digest,
        "area_json": json.dumps(area.to_dict(), sort_keys=True),
    }
    if area.water.depth_m is not None:
        attrs["water_depth_m"] = float(area.water.depth_m)
    else:
        attrs["origin_lat_deg"] = float(area.origin.lat_deg)
        attrs["origin_lon_deg"] = float(area.origin.lon_deg)
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def _unit(name: str) -> str:
    for suffix, unit in (("_km", "km"), ("_m", "m"), ("_mps", "m s-1"), ("_c", "degC"), ("_psu", "1e-3"),
                         ("_gcc", "g cm-3"), ("_db_per_wavelength", "dB/wavelength")):
        if name.endswith(suffix):
            return unit
    return "1"
