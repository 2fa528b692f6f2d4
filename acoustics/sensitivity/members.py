"""One member of a sensitivity study: its perturbed area through BELLHOP to K(r), and optionally TL.

K(r) per member (``tl=False``): one BELLHOP run per band (run frequency) whose sources are the
observer depth (for classes at or below ``reciprocity_min_depth_m``: TL by reciprocity, observer
-> class depth) and the near-surface class depths (direct, class depth -> observer), because
incoherent beams near the pressure-release surface are not reciprocal (docs/sensitivity.md).
With ``tl=True`` a member is a full grid build and keeps its TL (K then comes from the grid,
direct for every class).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from acoustics.bellhop.envfile import RunSpec, env_text
from acoustics.bellhop.runner import run_env
from acoustics.bellhop.shdfile import tl_from_pressure
from acoustics.depthinterp import tl_at_depths
from acoustics.grid import (BuildStats, freq_key, band_tl_from_runs, build_grid, run_frequencies_hz,
                            run_timeout_s)
from acoustics.kcurve import spectral_term_db
from acoustics.sensitivity.perturb import member_area
from acoustics.sensitivity.spec import RECIPROCITY_MIN_DEPTH_M, StudySpec
from envdata.area import Area


@dataclass(frozen=True)
class MemberResult:
    """One member (``member is None``: the nominal area): K(r), optional TL, drawn parameters."""

    member: int | None
    k_db: np.ndarray  # (class, band, range)
    params: dict[str, float]
    bellhop_seconds: float
    tl_db: np.ndarray | None = None  # (class, band, depth, range) on the nominal depth axis

    def to_record(self) -> dict[str, Any]:
        """The arrays and small values a resume cache stores (``acoustics.executor.ResultCache``)."""
        record = {"member": self.member, "k_db": self.k_db, "params": self.params,
                  "bellhop_seconds": self.bellhop_seconds}
        if self.tl_db is not None:
            record["tl_db"] = self.tl_db
        return record

    @classmethod
    def from_record(cls, record: Mapping[str, Any]) -> MemberResult:
        """The inverse of ``to_record``; a missing or mistyped entry raises KeyError or TypeError."""
        member = record["member"]
        if not (member is None or isinstance(member, int)) or not isinstance(record["params"], dict):
            raise TypeError("not a sensitivity member record")
        return cls(member=member, k_db=np.asarray(record["k_db"]), params=record["params"],
                   bellhop_seconds=float(record["bellhop_seconds"]), tl_db=record.get("tl_db"))


def member_key(member: int | None) -> str:
    """The member's name in the resume cache and on the cluster: ``nominal`` or ``member-000042``."""
    return "nominal" if member is None else f"member-{member:06d}"


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
            result = run_env(env_text(area, spec), exe=exe, timeout_s=run_timeout_s(
                area, spec.n_beams, len(spec.source_depth_m) * len(receivers) * len(ranges)))
            seconds += result.seconds
            by_freq[freq_key(f)] = tl_from_pressure(result.field.pressure, prop.tl_max_db)
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
    # the member's TL on the nominal area's depths (its own bottom may be shallower: NaN below)
    tl = tl_at_depths(grid["tl_db"].values, grid["depth"].values, spec.area.depth_m()).astype(np.float32)
    return MemberResult(member=member, k_db=grid["k_db"].values, params=params,
                        bellhop_seconds=stats.bellhop_seconds, tl_db=tl)
