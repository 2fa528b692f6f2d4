"""Environmental sensitivity studies: an ensemble of perturbed areas run on a Dask cluster.

Each member is the area perturbed by ``acoustics.perturb`` with its own generator
``np.random.default_rng([seed, member])`` and its K(r) recomputed by BELLHOP; one Dask task is
one member (its BELLHOP runs inside), so the result does not depend on how many workers there
are or which worker ran what. Finished members are kept in a cache folder, so an interrupted
study resumes without redoing them.

K(r) per member (``tl=False``): one BELLHOP run per band (run frequency) whose sources are the
observer depth (for classes at or below ``reciprocity_min_depth_m``: TL by reciprocity, observer
-> class depth) and the near-surface class depths (direct, class depth -> observer), because
incoherent beams near the pressure-release surface are not reciprocal (docs/sensitivity.md).
With ``tl=True`` every member is a full grid build and ``tl_db(member, class, band, depth,
range)`` is kept too (K then comes from the grid, direct for every class).

The summaries compare each member with the nominal area computed the same way: bias and sd of
K(r), the part of the error that is a constant offset (Grinenkov & Mashoshin take dK as a
constant offset, sd 1.5 dB surface / 2.0 dB submarine), and the range error of level-based
ranging (eq. 20) when the tables are the nominal ones but the sea is the member.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr
from tqdm import tqdm

from acoustics.bellhop.envfile import RunSpec, env_text
from acoustics.bellhop.exe import find_bellhop
from acoustics.bellhop.runner import run_env
from acoustics.bellhop.shdfile import tl_from_pressure
from acoustics.errors import BellhopError
from acoustics.grid import TMAKIT_VERSION, BuildStats, _fkey, band_tl_from_runs, build_grid, run_frequencies_hz
from acoustics.io import load_netcdf, write_netcdf
from acoustics.kcurve import spectral_term_db
from acoustics.perturb import Perturbation, PerturbationError, check_perturbations, member_area
from envdata.area import Area
from envdata.errors import InputError
from envdata.files import atomic_path

log = logging.getLogger(__name__)

STUDY_FORMAT_VERSION = 1
# Classes at least this deep get K by reciprocity (one source at the observer serves them all);
# shallower ones directly. Measured on ocean-deep: reciprocity is within 0.1 dB (median) for the
# 200 m class, 2.3-2.4 dB off for the 6-8 m classes (docs/sensitivity.md, bench/bench_sensitivity.py).
RECIPROCITY_MIN_DEPTH_M = 50.0
DEFAULT_EVAL_RANGES_M = (5000.0, 10000.0, 20000.0, 50000.0, 100000.0)


@dataclass(frozen=True, slots=True, kw_only=True)
class StudySpec:
    """Everything that determines a study's numbers."""

    area: Area
    perturbations: tuple[Perturbation, ...]
    members: int
    seed: int = 0
    tl: bool = False
    reciprocity_min_depth_m: float = RECIPROCITY_MIN_DEPTH_M

    def __post_init__(self) -> None:
        if not 1 <= self.members <= 100_000:
            raise InputError(f"--members: must be in [1, 100000], got {self.members}")
        if not 0 <= self.seed < 2 ** 63:
            raise InputError(f"--seed: must be in [0, 2^63), got {self.seed}")
        if not (np.isfinite(self.reciprocity_min_depth_m) and self.reciprocity_min_depth_m >= 0):
            raise InputError(f"reciprocity_min_depth_m: must be >= 0 m, got {self.reciprocity_min_depth_m}")
        check_perturbations(self.area, list(self.perturbations))

    def digest(self, bellhop_sha256: str | None) -> str:
        payload = {"area": self.area.to_dict(), "perturbations": [p.to_dict() for p in self.perturbations],
                   "seed": self.seed, "tl": self.tl, "reciprocity_min_depth_m": self.reciprocity_min_depth_m,
                   "format": STUDY_FORMAT_VERSION, "tmakit": TMAKIT_VERSION, "bellhop_sha256": bellhop_sha256}
        return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()


@dataclass(frozen=True)
class MemberResult:
    """One member (``member is None``: the nominal area): K(r), optional TL, drawn parameters."""

    member: int | None
    k_db: np.ndarray  # (class, band, range)
    params: dict[str, float]
    bellhop_seconds: float
    tl_db: np.ndarray | None = None  # (class, band, depth, range) on the nominal depth axis


@dataclass
class StudyStats:
    members_total: int = 0
    members_reused: int = 0
    bellhop_seconds: float = 0.0  # BELLHOP process time of the members computed now (nominal included)
    wall_seconds: float = 0.0
    workers: int = 0


# --------------------------------------------------------------------------- one member


def k_runs(area: Area, reciprocity_min_depth_m: float = RECIPROCITY_MIN_DEPTH_M
           ) -> tuple[list[float], list[float], dict[str, tuple[int, int]]]:
    """Source depths, receiver depths and, per class, the (source, receiver) index of its TL."""
    obs = area.observer.depth_m
    deep = sorted({c.depth_m for c in area.classes if c.depth_m >= reciprocity_min_depth_m})
    shallow = sorted({c.depth_m for c in area.classes if c.depth_m < reciprocity_min_depth_m})
    sources = sorted(set(shallow) | ({obs} if deep else set()))
    receivers = sorted({obs} | set(deep))
    where = {}
    for cls in area.classes:
        if cls.depth_m >= reciprocity_min_depth_m:
            where[cls.name] = (sources.index(obs), receivers.index(cls.depth_m))  # reciprocity
        else:
            where[cls.name] = (sources.index(cls.depth_m), receivers.index(obs))  # direct
    return sources, receivers, where


def compute_k(area: Area, *, reciprocity_min_depth_m: float = RECIPROCITY_MIN_DEPTH_M,
              exe: str | None = None) -> tuple[np.ndarray, float]:
    """K(r) at the observer depth, ``(class, band, range)`` dB, and the BELLHOP seconds it took.

    One BELLHOP run per run frequency with several sources (see the module docstring); band TL
    as in ``acoustics.grid`` and K = spectral term - band TL (Grinenkov & Mashoshin eqs. 12-13).
    """
    prop = area.propagation
    sources, receivers, where = k_runs(area, reciprocity_min_depth_m)
    ranges = tuple(float(r) for r in area.grid.range_m())
    k = np.empty((len(area.classes), len(area.bands), len(ranges)))
    seconds = 0.0
    for ib, band in enumerate(area.bands):
        by_freq = {}
        for f in run_frequencies_hz(area, band):
            spec = RunSpec(title=f"tmakit sensitivity {area.name} f={f:.3f} Hz", freq_hz=float(f),
                           source_depth_m=tuple(sources), receiver_depth_m=tuple(receivers), range_m=ranges,
                           mode=prop.mode, beam_type=prop.beam_type, n_beams=prop.n_beams,
                           angle_min_deg=prop.angle_min_deg, angle_max_deg=prop.angle_max_deg,
                           absorption=prop.absorption)
            result = run_env(env_text(area, spec), exe=exe)
            seconds += result.seconds
            by_freq[_fkey(f)] = tl_from_pressure(result.field.pressure, prop.tl_max_db)
        for ic, cls in enumerate(area.classes):
            isrc, ircv = where[cls.name]
            tl = {key: field[isrc, ircv][None, :] for key, field in by_freq.items()}
            k[ic, ib] = spectral_term_db(cls, band) - band_tl_from_runs(area, cls, band, tl)[0]
    return k, seconds


def compute_member(spec: StudySpec, member: int | None, exe: str | None = None) -> MemberResult:
    """Member ``member`` of the study (``None``: the nominal area); runs BELLHOP in this process."""
    if member is None:
        area, params = spec.area, {}
    else:
        area, params = member_area(spec.area, list(spec.perturbations), spec.seed, member)
    if not spec.tl:
        k, seconds = compute_k(area, reciprocity_min_depth_m=spec.reciprocity_min_depth_m, exe=exe)
        return MemberResult(member=member, k_db=k, params=params, bellhop_seconds=seconds)
    stats = BuildStats()
    grid = build_grid(area, workers=1, stats=stats)
    tl = _on_depths(grid["tl_db"].values, grid["depth"].values, spec.area.depth_m())
    return MemberResult(member=member, k_db=grid["k_db"].values, params=params,
                        bellhop_seconds=stats.bellhop_seconds, tl_db=tl)


def _on_depths(tl: np.ndarray, depth_m: np.ndarray, target_m: np.ndarray) -> np.ndarray:
    """TL (..., depth, range) interpolated linearly onto ``target_m``; NaN below the member's bottom."""
    out = np.full(tl.shape[:-2] + (target_m.size, tl.shape[-1]), np.nan, dtype=np.float32)
    i = np.clip(np.searchsorted(depth_m, target_m) - 1, 0, depth_m.size - 2)
    w = (target_m - depth_m[i]) / (depth_m[i + 1] - depth_m[i])
    inside = target_m <= depth_m[-1] + 1e-9
    w = np.clip(w, 0.0, 1.0)[:, None]
    out[..., inside, :] = ((1 - w) * tl[..., i, :] + w * tl[..., i + 1, :])[..., inside, :]
    return out


# --------------------------------------------------------------------------- the ensemble


def run_study(area: Area, perturbations: Sequence[Perturbation], *, members: int, seed: int = 0,
              tl: bool = False, scheduler: str | None = None, workers: int = 1,
              cache_dir: str | Path | None = None, progress: bool = False,
              stats: StudyStats | None = None,
              reciprocity_min_depth_m: float = RECIPROCITY_MIN_DEPTH_M,
              on_result: Callable[[MemberResult], None] | None = None) -> xr.Dataset:
    """Run the ensemble and return the study dataset (``k_db(member, class, band, range)``).

    Parameters
    ----------
    area : Area
        The nominal area.
    perturbations : sequence of Perturbation
        What is uncertain (``acoustics.perturb``); checked at +-4 sd before anything runs.
    members : int
        Ensemble size.
    seed : int
        Member m draws from ``np.random.default_rng([seed, m])``.
    tl : bool
        Full grid per member and keep ``tl_db(member, class, band, depth, range)``.
    scheduler : str, optional
        Address of a Dask distributed scheduler; default: an in-process local cluster of
        ``workers`` single-threaded workers.
    cache_dir : path, optional
        Folder for finished members (resume); the caller removes it once the file is written.
    on_result : callable, optional
        Called in the calling thread with each member's result as it arrives (not for reused ones).
    """
    spec = StudySpec(area=area, perturbations=tuple(perturbations), members=members, seed=seed, tl=tl,
                     reciprocity_min_depth_m=reciprocity_min_depth_m)
    if scheduler is None and workers < 1:
        raise InputError(f"--workers: must be >= 1, got {workers}")
    stats = stats if stats is not None else StudyStats()
    start = time.perf_counter()
    exe = find_bellhop()
    digest = spec.digest(exe.sha256)
    cache = Path(cache_dir) if cache_dir is not None else None
    results: dict[int | None, MemberResult] = {}
    wanted: list[int | None] = [None, *range(members)]
    if cache is not None and cache.is_dir():
        for m in wanted:
            found = _load_member(cache, m)
            if found is not None:
                results[m] = found
    stats.members_total = members
    stats.members_reused = sum(1 for m in results if m is not None)
    todo = [m for m in wanted if m not in results]
    bar = tqdm(total=len(wanted), initial=len(results), desc="sensitivity members", unit="member",
               disable=not progress, file=sys.stderr, dynamic_ncols=True)
    try:
        if todo:
            for result in _execute(spec, todo, scheduler, workers, str(exe.path), digest, stats):
                results[result.member] = result
                stats.bellhop_seconds += result.bellhop_seconds
                if cache is not None:
                    _save_member(cache, result)
                bar.update(1)
                if on_result is not None:
                    on_result(result)
    finally:
        bar.close()
    ds = _dataset(spec, results, digest, exe.describe())
    stats.wall_seconds = time.perf_counter() - start
    return ds


def _execute(spec: StudySpec, todo: list[int | None], scheduler: str | None, workers: int, exe: str,
             digest: str, stats: StudyStats):
    from distributed import Client, LocalCluster
    from distributed import as_completed as dask_as_completed

    cluster = None
    if scheduler is None:
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=False,
                               dashboard_address=":0",  # any free port: never collide with 8787
                               silence_logs=logging.WARNING)
        client = Client(cluster)
    else:
        try:
            client = Client(scheduler, timeout="5s")
        except (OSError, TimeoutError, ValueError) as exc:
            raise InputError(f"--scheduler {scheduler}: cannot connect to a Dask scheduler "
                             f"({type(exc).__name__}: {exc})") from None
    try:
        stats.workers = len(client.scheduler_info().get("workers", {}))
        futures = [client.submit(compute_member, spec, m, exe, pure=False, retries=1,
                                 key=f"tmakit-sensitivity-{digest[:12]}-{'nominal' if m is None else m}")
                   for m in todo]
        for future in dask_as_completed(futures):
            if future.status == "error":
                exc = future.exception()
                name = _key_member(future.key)
                if isinstance(exc, (BellhopError, InputError)):
                    raise exc
                raise BellhopError(f"sensitivity member {name} failed on the Dask cluster: "
                                   f"{type(exc).__name__}: {exc}")
            yield future.result()
            future.release()
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def _key_member(key) -> str:
    return str(key).rsplit("-", 1)[-1]


def _member_file(cache: Path, member: int | None) -> Path:
    return cache / ("nominal.npz" if member is None else f"member-{member:06d}.npz")


def _save_member(cache: Path, result: MemberResult) -> None:
    cache.mkdir(parents=True, exist_ok=True)
    path = _member_file(cache, result.member)
    tmp = path.with_name(f".{path.stem}.{os.getpid()}.npz")
    arrays = {"k_db": result.k_db, "bellhop_seconds": np.float64(result.bellhop_seconds),
              "params": np.array(json.dumps(result.params))}
    if result.tl_db is not None:
        arrays["tl_db"] = result.tl_db
    np.savez(tmp, **arrays)
    os.replace(tmp, path)


def _load_member(cache: Path, member: int | None) -> MemberResult | None:
    path = _member_file(cache, member)
    if not path.exists():
        return None
    try:
        with np.load(path) as data:
            return MemberResult(member=member, k_db=data["k_db"], params=json.loads(str(data["params"])),
                                bellhop_seconds=0.0,
                                tl_db=data["tl_db"] if "tl_db" in data.files else None)
    except (OSError, ValueError, KeyError):
        path.unlink()  # a damaged cache entry is simply recomputed
        return None


def _dataset(spec: StudySpec, results: dict[int | None, MemberResult], digest: str, exe_info: dict) -> xr.Dataset:
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
    dims3 = ("class", "band", "range")
    data_vars = {
        "k_db": (("member",) + dims3, k, {
            "units": "dB", "long_name": "transfer characteristic K(r) at the observer depth, perturbed member",
            "reference": "band level W = P0 + K(r) + H (Grinenkov & Mashoshin eq. 12)"}),
        "k_nominal_db": (dims3, nominal.k_db, {
            "units": "dB", "long_name": "transfer characteristic K(r) of the nominal area, same method"}),
    }
    if spec.tl:
        depth = area.depth_m()
        coords["depth"] = ("depth", depth, {"units": "m", "standard_name": "depth", "positive": "down",
                                            "axis": "Z", "long_name": "receiver depth"})
        data_vars["tl_db"] = (("member", "class", "band", "depth", "range"),
                              np.stack([results[int(m)].tl_db for m in members]),
                              {"units": "dB", "long_name": "band transmission loss, perturbed member",
                               "reference": "1 m from the source",
                               "comment": "NaN below the member's bottom"})
        data_vars["tl_nominal_db"] = (("class", "band", "depth", "range"), nominal.tl_db,
                                      {"units": "dB", "long_name": "band transmission loss, nominal area",
                                       "reference": "1 m from the source"})
    method = ("grid build per member (direct for every class)" if spec.tl else
              f"reciprocity for classes at or below {spec.reciprocity_min_depth_m:g} m, direct above")
    attrs = {
        "Conventions": "CF-1.8",
        "title": f"tmakit environmental sensitivity study for area {area.name}",
        "institution": "tmakit",
        "source": f"tmakit {TMAKIT_VERSION}, model bellhop",
        "references": "Grinenkov & Mashoshin (2024) eqs. 12-13, 20; Porter, The BELLHOP manual (2011)",
        "comment": "dB quantities carry units 'dB' with their reference in the 'reference' attribute",
        "area": area.name,
        "model": "bellhop",
        "observer_depth_m": float(area.observer.depth_m),
        "water_depth_m": float(area.water.depth_m),
        "seed": int(spec.seed),
        "members": int(spec.members),
        "perturbations": json.dumps([p.to_dict() for p in spec.perturbations]),
        "k_method": method,
        "reciprocity_min_depth_m": float(spec.reciprocity_min_depth_m),
        "bellhop_version": exe_info["version"],
        "bellhop_sha256": exe_info["sha256"],
        "created": _now(),
        "source_hash": digest,
        "area_json": json.dumps(area.to_dict(), sort_keys=True),
    }
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def _unit(name: str) -> str:
    for suffix, unit in (("_m", "m"), ("_mps", "m s-1"), ("_c", "degC"), ("_psu", "1e-3"), ("_gcc", "g cm-3"),
                         ("_db_per_wavelength", "dB/wavelength")):
        if name.endswith(suffix):
            return unit
    return "1"


def _now() -> str:
    from acoustics.grid import _now as now

    return now()


# --------------------------------------------------------------------------- files


REQUIRED_STUDY_VARS = {"k_db": ("member", "class", "band", "range"), "k_nominal_db": ("class", "band", "range")}


class StudyFileError(InputError):
    """A study file that is missing, not netCDF, or lacks what DESIGN.md requires."""


def write_study(ds: xr.Dataset, path: str | Path) -> Path:
    """Write the study (and any summaries merged into it) as netCDF4 via a temporary file."""
    return write_netcdf(ds, path)


def open_study(path: str | Path) -> xr.Dataset:
    """Open a study file, load it, and check the variables of DESIGN.md."""
    ds = load_netcdf(path, StudyFileError, "study")
    for name, dims in REQUIRED_STUDY_VARS.items():
        if name not in ds or ds[name].dims != dims:
            raise StudyFileError(f"{path}: missing variable {name}{dims}")
    return ds


# --------------------------------------------------------------------------- summaries


def level_range_m(k_levels_db: np.ndarray, k_table_db: np.ndarray, range_m: np.ndarray,
                  sigma_db: np.ndarray | None = None) -> np.ndarray:
    """Level-based range estimate, eq. 20: argmin_r sum_k (W_k - P0 - K_k(r) - H_k)^2 / sigma_k^2.

    Parameters
    ----------
    k_levels_db : ndarray, (..., band)
        Measured band levels minus P0 and H, i.e. the true K_k at the target's range, dB.
    k_table_db : ndarray, (band, range)
        The tables K_k(r) the ranging uses, dB.
    range_m : ndarray, (range,)
        Range axis of the tables, m.
    sigma_db : ndarray, (band,), optional
        Level error sd per band (eq. 11); equal weights by default.

    Returns
    -------
    range_m : ndarray, (...)
        The grid range minimising the weighted squared level misfit (all bands detected, I_k = 1).

    References
    ----------
    Grinenkov & Mashoshin (2024), eqs. 18-20.
    """
    levels = np.asarray(k_levels_db, dtype=float)
    table = np.asarray(k_table_db, dtype=float)
    w = np.ones(table.shape[0]) if sigma_db is None else 1.0 / np.asarray(sigma_db, dtype=float) ** 2
    cost = np.einsum("...kr,k->...r", (levels[..., :, None] - table) ** 2, w)
    return np.asarray(range_m)[np.argmin(cost, axis=-1)]


def summarize(ds: xr.Dataset, *, eval_ranges_m: Sequence[float] = DEFAULT_EVAL_RANGES_M,
              range_min_m: float | None = None, range_max_m: float | None = None) -> xr.Dataset:
    """Bias, sd, constant-offset share of dK(r) = K_member(r) - K_nominal(r), and the range error.

    Parameters
    ----------
    ds : Dataset
        A study from ``run_study`` or ``open_study``.
    eval_ranges_m : sequence of float
        True ranges at which the implied range error of level-based ranging (eq. 20) is given.
    range_min_m, range_max_m : float, optional
        Range window of the scalar summaries (default: the whole range axis).

    Returns
    -------
    Dataset
        ``k_bias_db`` and ``k_sd_db`` (class, band, range); over the window, per (class, band):
        ``k_offset_sd_db`` (sd over members of each member's mean dK, the constant part),
        ``k_residual_rms_db`` (what a constant offset leaves), ``k_constant_fraction`` (share of
        the mean-square dK that is a constant offset), ``k_rms_error_db``; per class
        ``k_error_sd_db`` (rms dK over members, bands and ranges: the measured value for the
        area file); per (class, eval_range) ``range_bias_m``, ``range_rms_m`` and
        ``range_error_m(member, class, eval_range)``; ``k_offset_correlation(class, parameter)``
        says which drawn parameter moves the constant part.
    """
    rng = ds["range"].values
    lo = rng[0] if range_min_m is None else range_min_m
    hi = rng[-1] if range_max_m is None else range_max_m
    inside = (rng >= lo) & (rng <= hi)
    if not inside.any():
        raise InputError(f"range window [{lo:g}, {hi:g}] m contains no range of the study "
                         f"({rng[0]:g}-{rng[-1]:g} m)")
    dk = ds["k_db"] - ds["k_nominal_db"]
    n = ds.sizes["member"]
    bias = dk.mean("member")
    sd = dk.std("member", ddof=1) if n > 1 else xr.zeros_like(bias) * np.nan
    win = dk.isel(range=inside)
    offset = win.mean("range")
    offset_sd = offset.std("member", ddof=1) if n > 1 else xr.zeros_like(offset.isel(member=0)) * np.nan
    ms = (win ** 2).mean(("member", "range"))
    residual = np.sqrt(((win - offset) ** 2).mean(("member", "range")))
    constant_fraction = xr.where(ms > 0, (offset ** 2).mean("member") / ms, 1.0)
    k_error = np.sqrt((win ** 2).mean(("member", "band", "range")))

    eval_r = np.asarray([r for r in eval_ranges_m if rng[0] <= r <= rng[-1]], dtype=float)
    idx = np.abs(rng[None, :] - eval_r[:, None]).argmin(axis=1) if eval_r.size else np.zeros(0, int)
    true_r = rng[idx]
    k_member = ds["k_db"].values[..., idx]  # (member, class, band, eval)
    k_nom = ds["k_nominal_db"].values  # (class, band, range)
    est = np.empty((n, ds.sizes["class"], idx.size))
    for ic in range(ds.sizes["class"]):
        levels = np.moveaxis(k_member[:, ic], 1, -1)  # (member, eval, band)
        est[:, ic] = level_range_m(levels, k_nom[ic], rng)
    err = est - true_r[None, None, :]
    # which drawn parameter drives the constant part: correlation over members of each parameter
    # with the member's offset (mean over bands and the window)
    params = [name for name, coord in ds.coords.items() if coord.dims == ("member",) and name != "member"]
    band_offset = offset.mean("band").values  # (member, class)
    corr = np.full((ds.sizes["class"], len(params)), np.nan)
    for j, name in enumerate(params):
        x = ds[name].values.astype(float)
        for ic in range(ds.sizes["class"]):
            y = band_offset[:, ic]
            if n > 2 and x.std() > 0 and y.std() > 0:
                corr[ic, j] = float(np.corrcoef(x, y)[0, 1])
    out = xr.Dataset(
        {
            "k_offset_correlation": (("class", "parameter"), corr,
                                     {"units": "1", "long_name": "correlation over members of a perturbation "
                                                                 "parameter with the member's mean K offset"}),
            "k_bias_db": (bias.dims, bias.values, {"units": "dB", "long_name": "mean over members of K - K_nominal"}),
            "k_sd_db": (sd.dims, sd.values, {"units": "dB", "long_name": "sd over members of K - K_nominal"}),
            "k_offset_sd_db": (offset_sd.dims, offset_sd.values,
                               {"units": "dB", "long_name": "sd over members of the range-mean of K - K_nominal"}),
            "k_residual_rms_db": (residual.dims, residual.values,
                                  {"units": "dB", "long_name": "rms of K - K_nominal after removing each "
                                                               "member's constant offset"}),
            "k_constant_fraction": (constant_fraction.dims, constant_fraction.values,
                                    {"units": "1", "long_name": "share of the mean-square K error that is a "
                                                                "constant offset per member"}),
            "k_rms_error_db": (ms.dims, np.sqrt(ms.values), {"units": "dB", "long_name": "rms of K - K_nominal"}),
            "k_error_sd_db": (k_error.dims, k_error.values,
                              {"units": "dB", "long_name": "measured sd of the transfer-characteristic error "
                                                           "(rms over members, bands and ranges)"}),
            "range_error_m": (("member", "class", "eval_range"), err,
                              {"units": "m", "long_name": "level-ranging (eq. 20) error with nominal tables"}),
            "range_bias_m": (("class", "eval_range"), err.mean(axis=0), {"units": "m"}),
            "range_rms_m": (("class", "eval_range"), np.sqrt((err ** 2).mean(axis=0)), {"units": "m"}),
        },
        coords={"member": ds["member"].values, "class": ds["class"].values, "band": ds["band"].values,
                "range": rng, "parameter": ("parameter", np.array(params, dtype=object)),
                "eval_range": ("eval_range", true_r, {"units": "m", "long_name": "true range"})},
        attrs={"summary_range_min_m": float(lo), "summary_range_max_m": float(hi)})
    return out


def k_error_by_class(summary: xr.Dataset) -> dict[str, float]:
    return {str(c): float(v) for c, v in zip(summary["class"].values, summary["k_error_sd_db"].values)}


# --------------------------------------------------------------------------- write-back


def write_k_error(area_file: str | Path, values: dict[str, float], out: str | Path) -> Path:
    """Copy the area TOML ``area_file`` to ``out`` with each class's ``k_error_sd_db`` replaced.

    Comments and layout are kept; a class without the key gets it after its ``name`` line. The
    copy is re-read with ``envdata.load_area`` before it replaces ``out``.
    """
    import re
    import tomllib

    from envdata.areafile import load_area

    text = Path(area_file).read_text(encoding="utf-8")
    lines = text.splitlines(keepends=True)
    header = re.compile(r"^\s*\[")
    starts = [i for i, line in enumerate(lines) if header.match(line)] + [len(lines)]
    done = set()
    out_lines = lines[:starts[0]]
    for a, b in zip(starts[:-1], starts[1:]):
        block = lines[a:b]
        if block[0].strip().startswith("[[classes]]"):
            name = tomllib.loads("".join(block[1:])).get("name")
            if name in values:
                value_line = f"k_error_sd_db = {values[name]:.2f}  # measured by tmakit sensitivity\n"
                key = re.compile(r"^\s*k_error_sd_db\s*=")
                hits = [j for j, line in enumerate(block) if key.match(line)]
                if hits:
                    block[hits[0]] = value_line
                else:
                    at = next(j for j, line in enumerate(block) if re.match(r"^\s*name\s*=", line))
                    block.insert(at + 1, value_line)
                done.add(name)
        out_lines += block
    missing = sorted(set(values) - done)
    if missing:
        raise InputError(f"{area_file}: no [[classes]] entry named {missing[0]!r} to write k_error_sd_db into")
    out = Path(out)
    with atomic_path(out) as tmp:
        tmp.write_text("".join(out_lines), encoding="utf-8")
        area = load_area(tmp)
        for cls in area.classes:
            if cls.name in values and abs(cls.k_error_sd_db - round(values[cls.name], 2)) > 1e-9:
                raise InputError(f"{area_file}: could not write k_error_sd_db of class {cls.name!r}")
    return out


__all__ = ["DEFAULT_EVAL_RANGES_M", "MemberResult", "PerturbationError", "RECIPROCITY_MIN_DEPTH_M",
           "StudyFileError", "StudySpec", "StudyStats", "compute_k", "compute_member", "k_error_by_class",
           "level_range_m", "open_study", "run_study", "summarize", "write_k_error", "write_study"]
