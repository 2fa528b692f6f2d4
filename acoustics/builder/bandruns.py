"""What both grid builders share (the isotropic ``acoustics.builder.flat`` and the radial
``acoustics.builder.radial``): the model choice, the build statistics, the frequencies BELLHOP runs
for a band, a band's TL from those runs, a run's time limit, and the hash of everything that
determines a grid's numbers.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field
from enum import StrEnum

import numpy as np

from acoustics.absorption import absorption_db_per_km
from acoustics.bellhop.runner import default_timeout_s
from acoustics.builder.runs import Run, RunStats
from acoustics.grid.dataset import TMAKIT_VERSION
from acoustics.kcurve import band_average_tl_db, band_frequencies_hz, band_weights
from envdata.area import Area, TlMode

GRID_FORMAT_VERSION = 1


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


def run_frequencies_hz(area: Area, band) -> np.ndarray:
    """Frequencies BELLHOP must run for ``band``: the centre (shortcut) or every quadrature point."""
    prop = area.propagation
    if prop.mode is TlMode.INCOHERENT and prop.frequency_shortcut:
        return np.array([band.center_hz])
    return band_frequencies_hz(band, prop.freqs_per_band)


def run_timeout_s(area: Area, n_beams: int, n_receivers: int) -> float:
    """The limit of one BELLHOP run: the area's ``[propagation] run_timeout_s`` or a generous
    default scaled to the run's beams x receivers (``bellhop.runner.default_timeout_s``), s."""
    limit = area.propagation.run_timeout_s
    return limit if limit is not None else default_timeout_s(n_beams, n_receivers)


def band_tl_from_runs(area: Area, cls, band, tl_by_freq: dict[float, np.ndarray]) -> np.ndarray:
    """Band TL for ``cls`` from the run TL fields of one source depth, keyed by run frequency."""
    prop = area.propagation
    freqs = band_frequencies_hz(band, prop.freqs_per_band)
    weights = band_weights(cls, freqs)
    range_km = area.grid.range_m() / 1000.0
    if prop.mode is TlMode.INCOHERENT and prop.frequency_shortcut:
        # TL(f_i) = TL(f_c) + (alpha_i - alpha_c) r, so the band intensity factors into the
        # centre intensity times a function of range alone: sum_i w_i 10^(-(alpha_i - alpha_c) r / 10)
        fc = band.center_hz
        base = tl_by_freq[freq_key(fc)].astype(np.float64)
        d_alpha = absorption_db_per_km(freqs, prop.absorption) - absorption_db_per_km(fc, prop.absorption)
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
