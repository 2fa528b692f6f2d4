"""Is an area's BELLHOP converged? K moved by doubling the beams, halving the ray step and giving
every quadrature frequency its own run, on a sample of radials (``tmakit grids check``).

Each variant computes K alone (receivers at the class depths and the observer's: what a grid's K
rows are, without its TL table) with one setting changed, and is compared with the area's own:
the median over classes, bands, bearings and ranges of |dK|, and the worst class and band's
median. A setting is converged when doubling it moves K by at most ``CONVERGED_DB`` in the
median (DESIGN.md "Near-surface sources and the beam fan"); the worst class and band is said
beside it. A flat area's one profile is its
sample; a bearing-dependent area's sample is ``SAMPLE_RADIALS`` of its bearings, evenly spread.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass

import numpy as np

from acoustics.builder.bandruns import BuildStats, surface_acts, uses_shortcut
from acoustics.builder.kobserver import k_at_observer_db
from acoustics.builder.radial import DEFAULT_STEP_M, radial_k_db
from envdata.area import Area, TlMode
from envdata.geometry import Bearings

#: A setting is converged when doubling it moves K by at most this (median |dK|), dB.
CONVERGED_DB = 0.2
#: The sound speed that decides whether a class is within the surface's reach for the check's
#: choice of variants (a bearing-dependent area has no one profile), m/s.
NOMINAL_SPEED_MPS = 1500.0
#: Radials a bearing-dependent area's check runs.
SAMPLE_RADIALS = 3


@dataclass(frozen=True, slots=True)
class Variant:
    """One doubled setting: what it changed, |dK| median over everything and the worst class and
    band's median, dB, its runs' BELLHOP time, s, and whether the median is within
    ``CONVERGED_DB``."""

    name: str
    change: str
    median_db: float
    worst_db: float
    worst: str
    bellhop_seconds: float
    converged: bool


@dataclass(frozen=True, slots=True)
class CheckResult:
    """The area's settings as a build uses them, the sample, and each variant."""

    area: str
    settings: dict
    sample: str
    baseline_seconds: float
    variants: tuple[Variant, ...]

    @property
    def converged(self) -> bool:
        return all(v.converged for v in self.variants)


def build_settings(area: Area) -> dict:
    """What a build of ``area`` runs with: mode, beams and fan, ray step, frequencies per band and
    whether one run makes a band, the surface's arrivals run."""
    prop = area.propagation
    step = prop.step_m if prop.step_m is not None else (DEFAULT_STEP_M if area.is_bearing_dependent else None)
    return {"mode": str(prop.mode), "n_beams": prop.n_beams, "angle_min_deg": prop.angle_min_deg,
            "angle_max_deg": prop.angle_max_deg, "step_m": step, "freqs_per_band": prop.freqs_per_band,
            "one_run_per_band": uses_shortcut(area),
            "surface_image_beams": prop.image_beams if prop.mode is TlMode.SEMICOHERENT else None}


def _sample(area: Area) -> tuple[Area, str]:
    """The area restricted to its sample of radials, and a description of it."""
    if not area.is_bearing_dependent:
        return area, "the area's one profile"
    bearings = np.asarray(area.bearings.bearing_deg, dtype=float)
    spread = np.linspace(0, bearings.size - 1, min(SAMPLE_RADIALS, bearings.size)).round().astype(int)
    pick = bearings[np.unique(spread)]
    sample = dataclasses.replace(area, bearings=Bearings(listed_deg=tuple(float(b) for b in pick)))
    return sample, "radials at " + ", ".join(f"{b:g}" for b in pick) + " deg"


def _k(area: Area, workers: int) -> tuple[np.ndarray, float]:
    """K (class, band, [bearing,] range) and the runs' BELLHOP time."""
    stats = BuildStats()
    if area.is_bearing_dependent:
        k, _ = radial_k_db(area, workers=workers, stats=stats)
    else:
        k = k_at_observer_db(area, workers=workers, stats=stats)
    return k, stats.bellhop_seconds


def _variants(area: Area) -> list[tuple[str, str, Area]]:
    prop = area.propagation
    out = []
    semicoherent = prop.mode is TlMode.SEMICOHERENT
    if prop.n_beams > 0:  # the fan alone: the surface's arrivals run keeps its beams
        kept = {"surface_image_beams": prop.image_beams} if semicoherent else {}
        doubled = dataclasses.replace(prop, n_beams=2 * prop.n_beams, **kept)
        out.append(("beams", f"n_beams {prop.n_beams} -> {2 * prop.n_beams}",
                    dataclasses.replace(area, propagation=doubled)))
    near = any(surface_acts(area, b, c.depth_m, NOMINAL_SPEED_MPS) for c in area.classes for b in area.bands)
    if semicoherent and area.is_bearing_dependent and near:
        # the arrivals run that gives a table from the observer its near-surface rows
        n = prop.image_beams
        out.append(("surface_image_beams", f"surface_image_beams {n} -> {2 * n}",
                    dataclasses.replace(area, propagation=dataclasses.replace(prop, surface_image_beams=2 * n))))
    step = build_settings(area)["step_m"]
    if step is not None:
        out.append(("ray_step", f"step_m {step:g} -> {step / 2:g}",
                    dataclasses.replace(area, propagation=dataclasses.replace(prop, step_m=step / 2))))
    else:  # a flat area left to BELLHOP's automatic step, a tenth of the depth
        auto = area.water.depth_m / 10.0
        out.append(("ray_step", f"step_m automatic ({auto:g}) -> {auto / 2:g}",
                    dataclasses.replace(area, propagation=dataclasses.replace(prop, step_m=auto / 2))))
    doubled = dataclasses.replace(prop, freqs_per_band=2 * prop.freqs_per_band)
    out.append(("freqs_per_band", f"freqs_per_band {prop.freqs_per_band} -> {2 * prop.freqs_per_band}",
                dataclasses.replace(area, propagation=doubled)))
    if uses_shortcut(area):
        # against a run at each of four times the quadrature's frequencies (each with its own
        # frequency's Lloyd pattern): a reference that resolves the fringes in frequency
        n = 4 * prop.freqs_per_band
        out.append(("one_run_per_band", f"one run per band -> a run per frequency ({n} per band)",
                    dataclasses.replace(area, propagation=dataclasses.replace(prop, frequency_shortcut=False,
                                                                              freqs_per_band=n))))
    return out


def check_area(area: Area, *, workers: int = 1, progress: bool = False) -> CheckResult:
    """Run the baseline and every variant on the area's sample and compare their K."""
    sample, description = _sample(area)
    start = time.perf_counter()
    base, base_seconds = _k(sample, workers)
    del start
    names = [(c.name, b.name) for c in area.classes for b in area.bands]
    variants = []
    for name, change, varied in _variants(sample):
        k, seconds = _k(varied, workers)
        d = np.abs(k - base)
        ok = np.isfinite(d) & (base > -150.0)
        per = []
        for ic in range(d.shape[0]):
            for ib in range(d.shape[1]):
                cell = d[ic, ib][ok[ic, ib]]
                per.append(float(np.median(cell)) if cell.size else 0.0)
        worst = int(np.argmax(per))
        med = float(np.median(d[ok])) if ok.any() else 0.0
        variants.append(Variant(name=name, change=change, median_db=round(med, 3), worst_db=round(per[worst], 3),
                                worst=f"{names[worst][0]} {names[worst][1]}", bellhop_seconds=round(seconds, 2),
                                converged=med <= CONVERGED_DB))
    return CheckResult(area=area.name, settings=build_settings(area), sample=description,
                       baseline_seconds=round(base_seconds, 2), variants=tuple(variants))
