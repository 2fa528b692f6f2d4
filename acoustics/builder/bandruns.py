"""What both grid builders share (the isotropic ``acoustics.builder.flat`` and the radial
``acoustics.builder.radial``): the model choice, the build statistics, the frequencies BELLHOP runs
for a band and the source pattern of each run (the surface at a target that is the source), a
band's TL from those runs, a run's time limit, and the hash of everything that determines a
grid's numbers.

The surface (``acoustics.surface``): in the default semicoherent mode a run whose source is a
target within the surface's reach carries the band average of the Lloyd factor as its source
pattern (an incoherent run at the band centre otherwise identical to the others), so one run
still makes the band: measured against one semicoherent run per quadrature frequency (28 per
band, ocean-deep, the 6 m class), K differs by 0.06 / 0.17 / 0.20 dB median in FB1 / FB2 / FB3
(docs/models.md "The sea surface").
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import dataclass, field
from enum import StrEnum

import numpy as np

from acoustics.absorption import absorption_db_per_km
from acoustics.bellhop.runner import default_timeout_s
from acoustics.builder.runs import Run, RunStats
from acoustics.kcurve import band_average_tl_db, band_frequencies_hz, band_weights
from acoustics.surface import band_quadrature, incoherent_error_db, lloyd_factor, surface_reach_m
from acoustics.version import TMAKIT_VERSION
from envdata.area import Area, TlMode

#: 2: a table from the observer runs one field run per radial for every band (``shared_run_hz``)
GRID_FORMAT_VERSION = 2


class Model(StrEnum):
    """The propagation model of a grid: BELLHOP's beams, the Urick formula, the RAM parabolic
    equation, or RAM below a crossover frequency and BELLHOP above (``auto``,
    ``acoustics.builder.modelchoice``)."""

    BELLHOP = "bellhop"
    URICK = "urick"
    RAM = "ram"
    AUTO = "auto"

    @property
    def runs_bellhop(self) -> bool:
        return self in (Model.BELLHOP, Model.AUTO)

    @property
    def runs_ram(self) -> bool:
        return self in (Model.RAM, Model.AUTO)


@dataclass
class BuildStats(RunStats):
    """What a build did: runs planned and reused, BELLHOP and RAM time, total wall time."""

    runs: list[Run] = field(default_factory=list)
    ram_seconds: float = 0.0  # sum of the RAM runs' times (in their worker processes)


def uses_shortcut(area: Area) -> bool:
    """Whether one run at a band's centre makes the band (incoherent beams, with or without the
    semicoherent source pattern): frequency then acts only through volume absorption."""
    prop = area.propagation
    return prop.mode is not TlMode.COHERENT and prop.frequency_shortcut


def run_frequencies_hz(area: Area, band) -> np.ndarray:
    """Frequencies BELLHOP must run for ``band``: the centre (shortcut) or every quadrature point."""
    if uses_shortcut(area):
        return np.array([band.center_hz])
    return band_frequencies_hz(band, area.propagation.freqs_per_band)


def shared_run_hz(area: Area) -> float:
    """The frequency of the one field run that serves every band of a table from the observer
    (one run per radial, no source pattern) where one run makes a band (``uses_shortcut``): the
    centre of the middle band (of two, the lower). Incoherent beams with a bottom whose
    attenuation is per wavelength depend on frequency only through volume absorption, so each
    band is that run with its own absorption put back by range (``band_tl_from_runs``).
    Measured on shelf-break's radials against a run at each band's centre (bench/bench_surface_
    candidates.py, docs/results/surface-candidates.json)."""
    centres = sorted(band.center_hz for band in area.bands)
    return float(centres[(len(centres) - 1) // 2])


def field_run_frequencies_hz(area: Area) -> list[float]:
    """The frequencies of the field runs that make every band of a table from the observer: the
    one run that serves them all where one run makes a band (`shared_run_hz`), else every band's
    quadrature points; each once, keyed as the runs are (`freq_key`)."""
    freqs = [shared_run_hz(area)] if uses_shortcut(area) else \
        [f for band in area.bands for f in run_frequencies_hz(area, band)]
    return list(dict.fromkeys(freq_key(f) for f in freqs))


def surface_acts(area: Area, band, depth_m: float, speed_mps: float) -> bool:
    """Whether a target end at ``depth_m`` gets the surface's interference in ``band``: the
    semicoherent mode, and the end within the surface's reach (``acoustics.surface``)."""
    return area.propagation.mode is TlMode.SEMICOHERENT and depth_m < surface_reach_m(band, speed_mps)


@dataclass(frozen=True, slots=True)
class SourcePattern:
    """A run's source beam pattern: intensity in dB at the fan's beam angles (deg)."""

    angle_deg: tuple[float, ...]
    level_db: tuple[float, ...]

    @property
    def pairs(self) -> tuple[tuple[float, float], ...]:
        return tuple(zip(self.angle_deg, self.level_db))

    @property
    def key(self) -> str:
        return hashlib.sha256(json.dumps([self.angle_deg, self.level_db]).encode()).hexdigest()[:16]


#: A pattern's floor, dB: BELLHOP reads the pattern in dB (zero intensity has none).
PATTERN_FLOOR_DB = -300.0


def fan_angles_deg(area: Area) -> np.ndarray:
    """The beam angles of the area's fan, deg (BELLHOP's automatic count: a 0.01 deg grid)."""
    prop = area.propagation
    n = prop.n_beams if prop.n_beams > 1 else int(round((prop.angle_max_deg - prop.angle_min_deg) / 0.01)) + 1
    return np.linspace(prop.angle_min_deg, prop.angle_max_deg, n)


def run_pattern(area: Area, cls, band, run_hz: float, depth_m: float, speed_mps: float) -> SourcePattern | None:
    """The source pattern of the run at ``run_hz`` for ``band`` from a target of ``cls`` at
    ``depth_m``: the Lloyd factor averaged over the frequencies the run stands for (the band's
    quadrature for the one-run shortcut, the run's own frequency otherwise); None where the
    surface does not act (``surface_acts``)."""
    if not surface_acts(area, band, depth_m, speed_mps):
        return None
    if uses_shortcut(area):
        freqs, weights = band_quadrature(cls, band, depth_m, speed_mps)
    else:
        freqs, weights = np.array([run_hz]), np.ones(1)
    angles = fan_angles_deg(area)
    g = lloyd_factor(depth_m, speed_mps, freqs, weights, angles)
    level = np.maximum(10.0 * np.log10(np.maximum(g, 1e-300)), PATTERN_FLOOR_DB)
    return SourcePattern(angle_deg=tuple(float(a) for a in angles),
                         level_db=tuple(round(float(v), 4) for v in level))


def run_timeout_s(area: Area, n_beams: int, n_receivers: int) -> float:
    """The limit of one BELLHOP run: the area's ``[propagation] run_timeout_s`` or a generous
    default scaled to the run's beams x receivers (``bellhop.runner.default_timeout_s``), s."""
    limit = area.propagation.run_timeout_s
    return limit if limit is not None else default_timeout_s(n_beams, n_receivers)


def band_tl_from_runs(area: Area, cls, band, tl_by_freq: dict[float, np.ndarray]) -> np.ndarray:
    """Band TL for ``cls`` from the run TL fields of one source depth, keyed by run frequency:
    where one run makes a band, the run at its centre or else the one run that serves every band
    (``shared_run_hz``)."""
    prop = area.propagation
    freqs = band_frequencies_hz(band, prop.freqs_per_band)
    weights = band_weights(cls, freqs)
    range_km = area.grid.range_m() / 1000.0
    if uses_shortcut(area):
        # TL(f_i) = TL(f_run) + (alpha_i - alpha_run) r, so the band intensity factors into the
        # run's intensity times a function of range alone: sum_i w_i 10^(-(alpha_i - alpha_run) r / 10)
        run_hz = freq_key(band.center_hz)
        run_hz = run_hz if run_hz in tl_by_freq else freq_key(shared_run_hz(area))
        base = tl_by_freq[run_hz].astype(np.float64)
        d_alpha = absorption_db_per_km(freqs, prop.absorption) - absorption_db_per_km(run_hz, prop.absorption)
        gain = weights @ 10.0 ** (-np.outer(d_alpha, range_km) / 10.0)
        band_tl = base - 10.0 * np.log10(gain)
        return np.minimum(band_tl, prop.tl_max_db)
    else:
        per_freq = np.stack([tl_by_freq[freq_key(f)].astype(np.float64) for f in freqs])
    return band_average_tl_db(per_freq, weights, prop.tl_max_db)


def freq_key(freq_hz: float) -> float:
    """A run frequency as a dictionary key (rounded to 1e-6 Hz)."""
    return round(float(freq_hz), 6)


def source_hash(area: Area, model: Model, bellhop_sha256: str | None,
                input_files: dict | None = None, ram_settings: dict | None = None) -> str:
    """Hash of everything that determines the grid's numbers: the area, the model, BELLHOP,
    the sha256 of the area's data files (``envdata.datafiles.input_file_digests``) and, for a
    grid with RAM runs, RAM's settings rule, frequencies per band and crossover."""
    payload = {"area": area.to_dict(), "model": str(model), "format": GRID_FORMAT_VERSION,
               "tmakit": TMAKIT_VERSION, "bellhop_sha256": bellhop_sha256}
    if ram_settings is not None:
        payload["ram"] = ram_settings
    if input_files:
        payload["inputs"] = {role: info["sha256"] for role, info in input_files.items()}
    return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()


#: A near-surface class's incoherent error is noted from this many dB.
NOTE_MIN_DB = 0.5
#: Sound speed assumed near the surface where the area's water is not one profile, m/s.
NOMINAL_SPEED_MPS = 1500.0


def incoherent_surface_notes(area: Area) -> list[str]:
    """One line per class within the surface's reach when the area's beams are incoherent: how
    much louder the tables make it than the surface lets it be, per band (``acoustics.surface.
    incoherent_error_db`` over the angles the bottom traps at its depth); none otherwise."""
    prop = area.propagation
    if prop.mode is not TlMode.INCOHERENT:
        return []
    notes = []
    for cls in area.classes:
        speed = float(area.water.ssp.speed_at(cls.depth_m)) if area.water.ssp is not None else NOMINAL_SPEED_MPS
        if not any(cls.depth_m < surface_reach_m(band, speed) for band in area.bands):
            continue
        trapped = math.degrees(math.acos(min(1.0, speed / area.bottom.speed_mps)))
        widest = min(trapped, max(abs(prop.angle_min_deg), abs(prop.angle_max_deg)))
        loud = [(band.name, -incoherent_error_db(cls, band, cls.depth_m, speed, widest))
                for band in area.bands if cls.depth_m < surface_reach_m(band, speed)]
        loud = [f"{db:.1f} dB in {name}" for name, db in loud if db >= NOTE_MIN_DB]
        if loud:
            notes.append(f"incoherent beams: class {cls.name} at {cls.depth_m:g} m comes out about "
                         f"{', '.join(loud)} too loud (the surface's interference, Lloyd's mirror; "
                         f"[propagation] mode = \"semicoherent\", the default, puts it in)")
    return notes
