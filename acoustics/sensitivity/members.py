"""One member of a sensitivity study: its perturbed area through BELLHOP to K(r), and optionally TL.

K(r) per member (``tl=False``): ``acoustics.builder.kobserver`` (one BELLHOP run per run
frequency whose sources are the observer depth, for classes at or below
``reciprocity_min_depth_m``: TL by reciprocity, observer -> class depth, and the near-surface
class depths, direct, class depth -> observer, because incoherent beams near the
pressure-release surface are not reciprocal, docs/sensitivity.md).
With ``tl=True`` a member is a full grid build and keeps its TL (K then comes from the grid,
direct for every class).

On an area with ``[origin]`` a member is a bearing-dependent grid: the perturbed area, and the
change to the data it reads (``envdata.fieldchange``), through the N x 2D runs of
``acoustics.builder.radial`` (the source at the observer, reciprocity for every class, as the
grids are built): K alone (``radial_k_db``, receivers at the class depths only), or with
``tl=True`` the whole grid, its TL kept on the nominal grid's depth axis.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from acoustics.builder.bandruns import BuildStats
from acoustics.builder.buildgrid import build_grid
from acoustics.builder.kobserver import k_at_observer_db
from acoustics.builder.radial import build_radial_grid, radial_k_db
from acoustics.grid.lookup import tl_at_depths
from acoustics.sensitivity.perturb import member_environment
from acoustics.sensitivity.spec import StudySpec
from envdata.radials import area_radials


@dataclass(frozen=True)
class MemberResult:
    """One member (``member is None``: the nominal area): K(r), optional TL, drawn parameters."""

    member: int | None
    k_db: np.ndarray  # (class, band, range), or (class, band, bearing, range) with [origin]
    params: dict[str, float]
    bellhop_seconds: float
    tl_db: np.ndarray | None = None  # (class, band[, bearing], depth, range) on the nominal depth axis
    depth_m: np.ndarray | None = None  # the nominal's depth axis of a bearing-dependent --tl study

    def to_record(self) -> dict[str, Any]:
        """The arrays and small values a resume cache stores (``acoustics.executor.ResultCache``)."""
        record = {"member": self.member, "k_db": self.k_db, "params": self.params,
                  "bellhop_seconds": self.bellhop_seconds}
        if self.tl_db is not None:
            record["tl_db"] = self.tl_db
        if self.depth_m is not None:
            record["depth_m"] = self.depth_m
        return record

    @classmethod
    def from_record(cls, record: Mapping[str, Any]) -> MemberResult:
        """The inverse of ``to_record``; a missing or mistyped entry raises KeyError or TypeError."""
        member = record["member"]
        if not (member is None or isinstance(member, int)) or not isinstance(record["params"], dict):
            raise TypeError("not a sensitivity member record")
        return cls(member=member, k_db=np.asarray(record["k_db"]), params=record["params"],
                   bellhop_seconds=float(record["bellhop_seconds"]), tl_db=record.get("tl_db"),
                   depth_m=record.get("depth_m"))


def member_key(member: int | None) -> str:
    """The member's name in the resume cache and on the cluster: ``nominal`` or ``member-000042``."""
    return "nominal" if member is None else f"member-{member:06d}"


def compute_member(spec: StudySpec, member: int | None, exe: str | None = None,
                   nominal_depth_m: np.ndarray | None = None, radials: list | None = None) -> MemberResult:
    """Member ``member`` of the study (``None``: the nominal area); runs BELLHOP in this process.

    ``nominal_depth_m``: the depth axis a bearing-dependent member's TL is put on (``tl``; the
    nominal's own, which its result carries in ``depth_m``). ``radials``: the member's radials
    already cut (`member_radials`), else they are cut here.
    """
    if member is None:
        area, change, params = spec.area, None, {}
    else:
        area, change, params = member_environment(spec.area, list(spec.perturbations), spec.seed, member)
    if area.is_bearing_dependent:
        if radials is None:
            radials = area_radials(area, change=change)
        return _radial_member(spec, member, area, radials, params, exe, nominal_depth_m)
    if not spec.tl:
        stats = BuildStats()
        k = k_at_observer_db(area, reciprocity_min_depth_m=spec.reciprocity_min_depth_m, exe=exe, stats=stats)
        return MemberResult(member=member, k_db=k, params=params, bellhop_seconds=stats.bellhop_seconds)
    stats = BuildStats()
    grid = build_grid(area, workers=1, stats=stats)
    # the member's TL on the nominal area's depths (its own bottom may be shallower: NaN below)
    tl = tl_at_depths(grid["tl_db"].values, grid["depth"].values, spec.area.depth_m()).astype(np.float32)
    return MemberResult(member=member, k_db=grid["k_db"].values, params=params,
                        bellhop_seconds=stats.bellhop_seconds, tl_db=tl)


def member_radials(spec: StudySpec, member: int | None) -> list:
    """The radials of member ``member`` (None: the nominal area) of a bearing-dependent study.

    Cut where this is called: a study cuts every member's radials on its own thread before the
    members run, since the data files are netCDF, whose libraries (netCDF-C, HDF5) are not
    thread-safe, and the members run on threads.
    """
    if member is None:
        return area_radials(spec.area)
    area, change, _ = member_environment(spec.area, list(spec.perturbations), spec.seed, member)
    return area_radials(area, change=change)


def _radial_member(spec: StudySpec, member, area, radials, params, exe, nominal_depth_m) -> MemberResult:
    stats = BuildStats()
    if not spec.tl:
        k, _ = radial_k_db(area, exe=exe, stats=stats, radials=radials)
        return MemberResult(member=member, k_db=k, params=params, bellhop_seconds=stats.bellhop_seconds)
    grid = build_radial_grid(area, workers=1, stats=stats, exe=exe, radials=radials)
    depth = grid["depth"].values if nominal_depth_m is None else np.asarray(nominal_depth_m)
    tl = tl_at_depths(grid["tl_db"].values, grid["depth"].values, depth).astype(np.float32)
    return MemberResult(member=member, k_db=grid["k_db"].values, params=params,
                        bellhop_seconds=stats.bellhop_seconds, tl_db=tl, depth_m=depth)
