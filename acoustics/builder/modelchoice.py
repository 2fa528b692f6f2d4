"""Which model computes which frequency of a band: RAM, BELLHOP, or RAM below a crossover and
BELLHOP above it (``--model auto``), and a band's TL from the two.

A RAM band is the class-spectrum-weighted intensity average (``acoustics.kcurve``) of coherent
RAM runs at `RAM_FREQS_PER_BAND` log-spaced frequencies. With ``auto`` each of those frequencies
below `AUTO_CROSSOVER_HZ` is a RAM run and each at or above it takes BELLHOP's incoherent TL at
that frequency; a band at or above the crossover is BELLHOP's band exactly as ``--model
bellhop`` computes it, a band at or below it is RAM's (a band edge on the crossover does not
split the band).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from acoustics.absorption import absorption_db_per_km
from acoustics.builder.bandruns import (
    Model,
    band_tl_from_runs,
    freq_key,
    run_frequencies_hz,
    source_hash,
    uses_shortcut,
)
from acoustics.builder.ramruns import ram_settings_description
from acoustics.kcurve import band_average_tl_db, band_frequencies_hz, band_weights
from envdata.area import Area
from envdata.bands import Band
from envdata.classes import TargetClass
from envdata.datafiles import input_file_digests

if TYPE_CHECKING:  # xarray is imported beside the runs (acoustics.builder.preload)
    import xarray as xr

#: Coherent RAM runs per band (log-spaced across it). Measured (``python -m
#: bench.crosscheck.ram_band``, docs/results/ram-band.json): a 100-300 Hz band averaged from n
#: runs against 41 runs, point-wise over 1-10 km, is 1.14 dB median (2.87 dB 90th percentile) off
#: with 7 runs (BELLHOP's count), 0.76 dB with 11 and 0.40 dB (1.01 dB) with 21 on the Pekeris
#: waveguide; 0.72 / 0.42 / 0.20 dB on munk-1000 50-150 Hz. 21 is the least count tested that
#: keeps the fringes the band average should smooth under 0.5 dB median: each run carries its
#: frequency's interference pattern, which the average washes out only when the frequencies
#: sample its movement across the band.
RAM_FREQS_PER_BAND = 21

#: ``--model auto``: RAM below this frequency, BELLHOP at and above it, Hz: the FB1/FB2 edge.
#: Measured (``python -m bench.crosscheck.models_study --only crossover``,
#: docs/results/ram-crossover.json, docs/models.md): on the shelf-break's upslope radial to 10 km,
#: BELLHOP's band TL is 1.34, 1.03 and 0.82 dB (median) from RAM's in half-octave bands at 100,
#: 200 and 400 Hz, while a RAM band costs four times more per octave (the 400 Hz band ~900 s of
#: runs for one 10 km radial, BELLHOP's 0.3 s): above 300 Hz RAM's hours buy under 1 dB.
AUTO_CROSSOVER_HZ = 300.0


@dataclass(frozen=True, slots=True, kw_only=True)
class BandPlan:
    """Who computes one band.

    Attributes
    ----------
    band : Band
        The band.
    freqs_hz : tuple of float
        The frequencies its average is taken over, Hz: RAM's `RAM_FREQS_PER_BAND`, or for a
        BELLHOP band BELLHOP's own (``acoustics.builder.bandruns``).
    ram_hz : tuple of float
        Those computed by RAM runs, Hz.
    bellhop_hz : tuple of float
        Those taken from BELLHOP, Hz (all of them: a BELLHOP band).
    """

    band: Band
    freqs_hz: tuple[float, ...]
    ram_hz: tuple[float, ...]
    bellhop_hz: tuple[float, ...]

    @property
    def bellhop_only(self) -> bool:
        return not self.ram_hz


def band_plans(area: Area, model: Model, crossover_hz: float = AUTO_CROSSOVER_HZ) -> list[BandPlan]:
    """Who computes each band of ``area`` under ``model`` (``ram`` or ``auto``)."""
    plans = []
    for band in area.bands:
        freqs = tuple(float(f) for f in band_frequencies_hz(band, RAM_FREQS_PER_BAND))
        if model is Model.RAM:
            ram = freqs
        elif model is Model.AUTO:  # a band touching the crossover from one side is that side's
            ram = (freqs if band.high_hz <= crossover_hz else () if band.low_hz >= crossover_hz
                   else tuple(f for f in freqs if f < crossover_hz))
        else:
            raise ValueError(f"band_plans: model {model} has no RAM share")
        if not ram:  # wholly above the crossover: BELLHOP's band as --model bellhop has it
            bh = tuple(float(f) for f in run_frequencies_hz(area, band))
            plans.append(BandPlan(band=band, freqs_hz=bh, ram_hz=(), bellhop_hz=bh))
        else:
            plans.append(BandPlan(band=band, freqs_hz=freqs, ram_hz=ram,
                                  bellhop_hz=tuple(f for f in freqs if f not in ram)))
    return plans


def ram_run_hz(plans: list[BandPlan]) -> list[float]:
    """The RAM run frequencies of all bands, each once (a shared band edge is one run), Hz."""
    return list(dict.fromkeys(freq_key(f) for p in plans for f in p.ram_hz))


def bellhop_run_hz(area: Area, plans: list[BandPlan]) -> list[float]:
    """The BELLHOP run frequencies the plans need, each once, Hz: a BELLHOP band's own, and for
    a mixed band its centre (incoherent or semicoherent with the frequency shortcut, TL at the
    other frequencies follows by absorption) or each of its BELLHOP frequencies."""
    shortcut = uses_shortcut(area)
    out = []
    for p in plans:
        if p.bellhop_only:
            out.extend(run_frequencies_hz(area, p.band))
        elif p.bellhop_hz:
            out.extend([p.band.center_hz] if shortcut else p.bellhop_hz)
    return list(dict.fromkeys(freq_key(f) for f in out))


def planned_band_tl_db(area: Area, cls: TargetClass, plan: BandPlan, ram_tl: dict[float, np.ndarray],
                       bellhop_tl: dict[float, np.ndarray]) -> np.ndarray:
    """Band TL of ``cls`` under ``plan`` from the runs' TL fields keyed by ``freq_key``, dB.

    RAM's fields are TL at their frequency; BELLHOP's at a mixed band's other frequencies come
    from its centre run, TL(f) = TL(f_c) + (alpha(f) - alpha(f_c)) r, when the area runs BELLHOP
    incoherent or semicoherent with the frequency shortcut, else from the run at f. NaN (below
    the bottom, beyond land) stays NaN.
    """
    prop = area.propagation
    if plan.bellhop_only:
        return band_tl_from_runs(area, cls, plan.band, bellhop_tl)
    shortcut = uses_shortcut(area)
    range_km = area.grid.range_m() / 1000.0  # alpha in dB/km
    fields = []
    for f in plan.freqs_hz:
        if f in plan.ram_hz:
            fields.append(ram_tl[freq_key(f)].astype(np.float64))
        elif shortcut:
            fc = plan.band.center_hz
            d_alpha = float(absorption_db_per_km(f, prop.absorption) - absorption_db_per_km(fc, prop.absorption))
            fields.append(bellhop_tl[freq_key(fc)].astype(np.float64) + d_alpha * range_km)
        else:
            fields.append(bellhop_tl[freq_key(f)].astype(np.float64))
    weights = band_weights(cls, np.array(plan.freqs_hz))
    return band_average_tl_db(np.stack(fields), weights, prop.tl_max_db)  # NaN stays NaN


def model_settings(model: Model) -> dict | None:
    """What a grid records of its RAM share (attribute ``ram_settings``, and in its source hash):
    the settings rule, the runs per band and, for ``auto``, the crossover; None without RAM."""
    if not model.runs_ram:
        return None
    settings = dict(ram_settings_description(), freqs_per_band=RAM_FREQS_PER_BAND)
    if model is Model.AUTO:
        settings["crossover_hz"] = AUTO_CROSSOVER_HZ
    return settings


def grid_source_hash(area: Area, model: Model, bellhop_sha256: str | None) -> str:
    """``source_hash`` of a grid of ``area`` under ``model`` (``bandruns.source_hash``, with the
    RAM settings when the model runs RAM)."""
    return source_hash(area, model, bellhop_sha256, input_file_digests(area.water), model_settings(model))


def with_ram_attrs(ds: xr.Dataset, model: Model) -> xr.Dataset:
    """A grid built with RAM runs, saying so: attribute ``ram_settings`` (JSON of
    `model_settings`), RAM among the references, and ``tl_db``'s comment naming the models."""
    settings = model_settings(model)
    ds.attrs["ram_settings"] = json.dumps(settings, sort_keys=True)
    ds.attrs["references"] = (ds.attrs.get("references", "") + "; Collins, A split-step Pade solution "
                              "for the parabolic equation method, JASA 93 (1993) (RAM)")
    share = ("RAM (coherent, split-step Pade)" if model is Model.RAM else
             f"RAM below {AUTO_CROSSOVER_HZ:g} Hz, BELLHOP (incoherent) at and above")
    rest = ds["tl_db"].attrs.get("comment", "").replace("BELLHOP from", "computed from")
    ds["tl_db"].attrs["comment"] = (f"{share}; {RAM_FREQS_PER_BAND} log-spaced frequencies per band "
                                    f"(BELLHOP's own for a band wholly above the crossover); {rest}")
    return ds
