"""The sea-surface checks: tmakit's default tables for near-surface targets against references
that do not share the beams' approximation.

- the image-source solution: isovelocity water over a matched (non-reflecting) bottom under the
  pressure-release surface, p = exp(i k R1) / R1 - exp(i k R2) / R2 (R1, R2 the distances from
  the source and from its image at -z_s), a band averaging |p|^2 over its frequencies with the
  class's spectrum (docs/formats.md and DESIGN.md, "Near-surface sources");
- KRAKEN's coherent field (pelagic, in .venv-kraken: ``bench.crosscheck.kraken``) averaged over
  1 km of range (and over a band's frequencies), trapped modes only, so the beams' fan is
  limited to the trapped angles;
- the target-centred runs (the source at the target, its Lloyd pattern) for K from the observer.

Each case returns the table's values and the reference's on the same cells; the tests
(``tests/acoustics/test_surface.py``) bound the differences and ``surface_study`` writes the
measured figures to ``docs/results/surface.json``.
"""

from __future__ import annotations

import math
import tempfile
from pathlib import Path

import numpy as np

import acoustics
import envdata
from acoustics.kcurve import band_weights
from bench.crosscheck.kraken import flat_area, kraken_case, kraken_tl_db, munk_area

#: Sound speed of the image-source case, m/s.
ISO_SPEED_MPS = 1500.0


def _area(doc: dict, name: str, *, radial: bool = False) -> envdata.Area:
    """``doc`` as an area; with ``radial`` an origin and one bearing (the table from the observer)."""
    doc = {**doc, "area": {**doc["area"], "name": name}}
    if radial:
        doc["origin"] = {"lat_deg": 45.0, "lon_deg": -30.0}
        doc["bearings"] = {"bearing_deg": [0.0]}
        doc["area"] = {**doc["area"], "latitude_deg": 45.0, "longitude_deg": -30.0}
    return envdata.parse_area(doc, name)


def image_area(band: tuple[float, float], *, radial: bool = False, mode: str = "semicoherent") -> envdata.Area:
    """2000 m of 1500 m/s water over a matched bottom (no reflection), a 6 m ship, a 100 m
    observer, ranges to 10 km, the fan +-89 deg; no absorption."""
    doc = envdata.load_area("munk-1000").to_dict()
    doc["water"] = {"depth_m": 2000.0, "ssp_depth_m": [0.0, 2000.0], "ssp_speed_mps": [ISO_SPEED_MPS] * 2}
    doc["bottom"] = {"speed_mps": ISO_SPEED_MPS, "density_gcc": 1.0, "attenuation_db_per_wavelength": 0.0}
    doc["observer"] = {"depth_m": 100.0}
    doc["bands"] = [{"name": "B", "low_hz": band[0], "high_hz": band[1]}]
    doc["classes"] = [{**doc["classes"][0], "name": "SHIP", "depth_m": 6.0}]
    doc["propagation"] = {"mode": mode, "absorption": "none", "n_beams": 1500, "angle_min_deg": -89.0,
                          "angle_max_deg": 89.0, "step_m": 10.0}
    doc["grid"] = {"range_max_m": 10000.0, "range_step_m": 100.0, "depth_step_m": 20.0}
    return _area(doc, "image", radial=radial)


def image_tl_db(source_m: float, receiver_m, range_m, area: envdata.Area) -> np.ndarray:
    """The exact two-path band TL (receiver depth, range), dB re 1 m."""
    band, cls = area.bands[0], area.classes[0]
    freqs = np.array([band.center_hz]) if band.is_single_frequency else np.geomspace(band.low_hz, band.high_hz, 401)
    w = band_weights(cls, freqs)
    z = np.asarray(receiver_m, dtype=float)[:, None]
    r = np.asarray(range_m, dtype=float)[None, :]
    r1, r2 = np.hypot(r, z - source_m), np.hypot(r, z + source_m)
    intensity = 0.0
    for f, wf in zip(freqs, w):
        k = 2.0 * math.pi * f / ISO_SPEED_MPS
        intensity = intensity + wf * np.abs(np.exp(1j * k * r1) / r1 - np.exp(1j * k * r2) / r2) ** 2
    return -10.0 * np.log10(intensity)


def trapped_angle_deg(area: envdata.Area, depth_m: float) -> float:
    """The steepest angle at ``depth_m`` of a ray the bottom's speed still traps, deg."""
    return math.degrees(math.acos(float(area.water.ssp.speed_at(depth_m)) / area.bottom.speed_mps))


def munk_surface_area(band: tuple[float, float], *, radial: bool, mode: str = "semicoherent",
                      target_m: float = 6.0) -> envdata.Area:
    """The deep Munk channel (5000 m, no absorption) with a ship at ``target_m`` (6 m) and the
    100 m observer, the fan limited to the trapped angles at the source (the target, or the
    observer for a table from the observer), ranges to 100 km every 100 m."""
    base = munk_area()
    source = base.observer.depth_m if radial else target_m
    a = trapped_angle_deg(base, source)
    doc = base.to_dict()
    doc["bands"] = [{"name": "B", "low_hz": band[0], "high_hz": band[1]}]
    doc["classes"] = [{**doc["classes"][1], "name": "SW", "depth_m": target_m}]
    doc["propagation"] = {**doc.get("propagation", {}), "mode": mode, "angle_min_deg": -a, "angle_max_deg": a,
                          "step_m": 25.0}
    doc["grid"] = {"range_max_m": 100000.0, "range_step_m": 100.0, "depth_step_m": 50.0}
    return _area(doc, "munk-surface", radial=radial)


def shelf_surface_area(mode: str = "semicoherent") -> envdata.Area:
    """The 200 m shelf of the KRAKEN cross-check (1500 -> 1490 m/s, summer-like downward
    refraction) with a 5 m trawler at 250 Hz, the fan limited to the trapped angles, 20 km."""
    base = flat_area()
    a = trapped_angle_deg(base, 5.0)
    doc = base.to_dict()
    doc["bands"] = [{"name": "B", "low_hz": 250.0, "high_hz": 250.0}]
    doc["classes"] = [{**doc["classes"][0], "name": "TR", "depth_m": 5.0}]
    doc["propagation"] = {**doc.get("propagation", {}), "mode": mode, "angle_min_deg": -a, "angle_max_deg": a}
    doc["grid"] = {"range_max_m": 20000.0, "range_step_m": 50.0, "depth_step_m": 5.0}
    return _area(doc, "shelf-surface")


def km_average_db(tl_db: np.ndarray, step_m: float, width_m: float = 1000.0) -> np.ndarray:
    """Intensity mean over a moving window of ``width_m`` along the last axis, dB."""
    n = int(round(width_m / step_m)) + 1
    kernel = np.ones(n) / n
    intensity = 10.0 ** (-np.asarray(tl_db, dtype=float) / 10.0)
    smooth = np.apply_along_axis(lambda row: np.convolve(row, kernel, mode="same"), -1, intensity)
    return -10.0 * np.log10(smooth)


#: KRAKEN's ranges for the references, m: 50 m apart, averaged over 1 km onto the tables' ranges.
KRAKEN_STEP_M = 50.0


def kraken_band_db(area: envdata.Area, source_m: float, receivers_m, range_max_m: float,
                   tmp: Path, n_freqs: int = 15) -> tuple[np.ndarray, np.ndarray]:
    """KRAKEN's coherent TL averaged over the area's band (the class's spectrum, ``n_freqs``
    frequencies) and over 1 km: (receiver depth, range) on ``KRAKEN_STEP_M`` ranges, and those ranges."""
    band, cls = area.bands[0], area.classes[0]
    freqs = np.array([band.center_hz]) if band.is_single_frequency else np.geomspace(band.low_hz, band.high_hz, n_freqs)
    w = band_weights(cls, freqs)
    rng = np.arange(500.0, range_max_m + 1.0, KRAKEN_STEP_M)
    intensity = 0.0
    for f, wf in zip(freqs, w):
        out = kraken_tl_db(kraken_case(area, f, source_m, receivers_m, rng, incoherent=False), tmp, timeout_s=900.0)
        intensity = intensity + wf * 10.0 ** (-out["tl_db"] / 10.0)
    return km_average_db(-10.0 * np.log10(intensity), KRAKEN_STEP_M), rng


def stats(diff: np.ndarray) -> dict:
    """Median and 90th percentile of |d| and the mean of d, dB, rounded."""
    d = np.asarray(diff, dtype=float)
    return {"median_db": round(float(np.median(np.abs(d))), 2), "p90_db": round(float(np.percentile(np.abs(d), 90)), 2),
            "mean_db": round(float(np.mean(d)), 2), "cells": int(d.size)}


def image_flat_case(band, mode: str = "semicoherent") -> dict:
    """The flat grid's TL (source at the 6 m ship) at 20-1000 m, 1-10 km, against the image solution."""
    area = image_area(band, mode=mode)
    grid = acoustics.build_grid(area, workers=2)
    z, r = grid["depth"].values, grid["range"].values
    zs, rs = (z >= 20.0) & (z <= 1000.0), r >= 1000.0
    exact = image_tl_db(6.0, z[zs], r[rs], area)
    return stats(grid["tl_db"].values[0, 0][zs][:, rs] - exact)


def image_radial_case(band) -> dict:
    """The table from the 100 m observer: K of the 6 m ship and the near-surface rows, against
    the image solution (reciprocity: the target at depth z, the observer the receiver)."""
    area = image_area(band, radial=True)
    grid = acoustics.build_grid(area, workers=2)
    tables = acoustics.open_tables(grid)
    r = grid["range"].values
    rs = r >= 1000.0
    k_tl = tables.spectral_db(0, 0) - grid["k_db"].values[0, 0, 0][rs]
    out = {"k": stats(k_tl - image_tl_db(6.0, [100.0], r[rs], area)[0]), "rows": {}}
    z = grid["depth"].values
    for zz in z[(z > 0.0) & (z <= 40.0)]:
        row = grid["tl_db"].sel(depth=zz).values[0, 0, 0][rs]
        out["rows"][f"{zz:g}"] = stats(row - image_tl_db(float(zz), [100.0], r[rs], area)[0])
    return out


def munk_flat_case(band, mode: str = "semicoherent", target_m: float = 6.0) -> dict:
    """The flat grid's TL field from the ship (at ``target_m``, 6 m) beyond 5 km against KRAKEN
    (1 km averages)."""
    area = munk_surface_area(band, radial=False, mode=mode, target_m=target_m)
    grid = acoustics.build_grid(area, workers=2)
    z, r = grid["depth"].values, grid["range"].values
    zs = (z > 0.0) & (z < area.water.depth_m)
    with tempfile.TemporaryDirectory() as tmp:
        ref, rng = kraken_band_db(area, target_m, z[zs], float(r[-1]), Path(tmp))
    ref = ref[:, np.searchsorted(rng, r)]
    tl = grid["tl_db"].values[0, 0][zs]
    ok = (r >= 5000.0)[None, :] & (tl < 190.0) & (ref < 150.0)
    return stats((tl - ref)[ok])


def munk_radial_case(band, mode: str = "semicoherent") -> dict:
    """The table from the 100 m observer: the 6 m ship's loss to the observer (K's TL) beyond
    30 km against KRAKEN (1 km averages)."""
    area = munk_surface_area(band, radial=True, mode=mode)
    grid = acoustics.build_grid(area, workers=2)
    r = grid["range"].values
    tl = acoustics.open_tables(grid).spectral_db(0, 0) - grid["k_db"].values[0, 0, 0]
    with tempfile.TemporaryDirectory() as tmp:
        ref, rng = kraken_band_db(area, 6.0, np.array([area.observer.depth_m]), float(r[-1]), Path(tmp))
    ref = ref[0, np.searchsorted(rng, r)]
    ok = (r >= 30000.0) & (tl < 190.0) & (ref < 150.0)
    return stats((tl - ref)[ok])


def shelf_case(mode: str = "semicoherent") -> dict:
    """The flat shelf grid's TL field from the 5 m trawler at 2-20 km against KRAKEN (1 km averages)."""
    area = shelf_surface_area(mode)
    grid = acoustics.build_grid(area, workers=2)
    z, r = grid["depth"].values, grid["range"].values
    zs = (z > 0.0) & (z < area.water.depth_m)
    with tempfile.TemporaryDirectory() as tmp:
        ref, rng = kraken_band_db(area, 5.0, z[zs], float(r[-1]), Path(tmp))
    ref = ref[:, np.searchsorted(rng, r)]
    tl = grid["tl_db"].values[0, 0][zs]
    ok = (r >= 2000.0)[None, :] & (tl < 190.0) & (ref < 150.0)
    return stats((tl - ref)[ok])


def reciprocity_case(range_max_m: float = 40000.0, mode: str = "semicoherent", image_beams: int | None = None) -> dict:
    """ocean-deep (its bands, fan and beams): K of the SW (6 m) and TV (8 m) classes from the
    observer (one radial of the area with an origin) against the same from the targets' own
    runs (the flat grid), per class and band; ``image_beams`` the surface's arrivals run's beams
    (default the area's)."""
    doc = envdata.load_area("ocean-deep").to_dict()
    doc["grid"] = {**doc["grid"], "range_max_m": range_max_m}
    doc["propagation"] = {**doc.get("propagation", {}), "step_m": 25.0, "mode": mode}
    if image_beams is not None:
        doc["propagation"]["surface_image_beams"] = image_beams
    doc["classes"] = [c for c in doc["classes"] if c["depth_m"] < 50.0]
    flat = acoustics.build_grid(_area(doc, "recip-flat"), workers=2)
    radial = acoustics.build_grid(_area(doc, "recip-radial", radial=True), workers=2)
    r = flat["range"].values
    out = {}
    for ic, name in enumerate(flat["class"].values):
        for ib, band in enumerate(flat["band"].values):
            kf, kr = flat["k_db"].values[ic, ib], radial["k_db"].values[ic, ib, 0]
            ok = np.isfinite(kf) & np.isfinite(kr) & (kf > -150.0) & (r > 2000.0)
            out[f"{name} {band}"] = stats((kr - kf)[ok])
    return out
