"""The RAM test environments shared by the tests and the study scripts.

- Pekeris: 100 m of 1500 m/s water over a 1800 m/s, 1.8 g/cm3 lossless fluid half-space.
- ASA wedge (Jensen & Ferla 1990, the upslope benchmark): 25 Hz, source at 100 m, the bottom
  from 200 m at the source to the shore at 4 km, 1500 m/s water over 1700 m/s, 1.5 g/cm3,
  0.5 dB/wavelength, no volume absorption. Built as an ``envdata.Radial`` (flat 200 m behind
  the source, the shore at 4 km with the radials' 1 m of water) so that RAM and BELLHOP take it
  the way the bearing-dependent grid does: ``RamEnvironment.from_radial`` and
  ``acoustics.bellhop.radialfiles.radial_files``.
- Deep: the built-in ``munk-1000`` area (1000 m of Munk water over 1600 m/s, 1.8 g/cm3,
  0.8 dB/wavelength), as ``RamEnvironment.from_area``.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np

import envdata
from acoustics.ram import RamEnvironment
from envdata.area import Absorption, Area
from envdata.bottom import Bottom
from envdata.radials import SHORE_DEPTH_M, Radial

PEKERIS = {"water_depth_m": 100.0, "c1_mps": 1500.0, "c2_mps": 1800.0, "rho1_gcc": 1.0, "rho2_gcc": 1.8}
PEKERIS_SOURCE_DEPTH_M = 36.0

WEDGE_FREQ_HZ = 25.0
WEDGE_SOURCE_DEPTH_M = 100.0
WEDGE_RECEIVER_DEPTH_M = 30.0
WEDGE_SHORE_M = 4000.0
WEDGE_BOTTOM = Bottom(speed_mps=1700.0, density_gcc=1.5, attenuation_db_per_wavelength=0.5)


def pekeris_environment() -> RamEnvironment:
    """The Pekeris waveguide as a RAM environment."""
    p = PEKERIS
    return RamEnvironment(bathymetry_range_m=[0.0], bathymetry_depth_m=[p["water_depth_m"]],
                          ssp_range_m=[0.0], ssp_depth_m=[0.0, p["water_depth_m"]],
                          speed_mps=[[p["c1_mps"], p["c1_mps"]]],
                          bottom=Bottom(speed_mps=p["c2_mps"], density_gcc=p["rho2_gcc"]),
                          source_depth_m=PEKERIS_SOURCE_DEPTH_M)


def wedge_area() -> Area:
    """An area carrying the wedge's bottom and no volume absorption (the benchmark has none)."""
    base = envdata.load_area("munk-1000")
    return dataclasses.replace(base, bottom=WEDGE_BOTTOM,
                               propagation=dataclasses.replace(base.propagation, absorption=Absorption.NONE))


def wedge_radial() -> Radial:
    """The wedge as a radial: 200 m behind the source, 200 m -> the shore at 4 km ahead."""
    r = np.concatenate([[-5000.0], np.arange(0.0, WEDGE_SHORE_M + 1.0, 50.0)])
    depth = np.maximum(200.0 * (1.0 - np.clip(r, 0.0, None) / WEDGE_SHORE_M), SHORE_DEPTH_M)
    ssp_r = np.array([-5000.0, WEDGE_SHORE_M])
    ssp_z = np.array([0.0, 200.0])
    return Radial(bearing_deg=0.0, range_m=r, lat_deg=np.zeros_like(r), lon_deg=np.zeros_like(r),
                  bottom_depth_m=depth, land_range_m=WEDGE_SHORE_M, ssp_range_m=ssp_r, ssp_depth_m=ssp_z,
                  speed_mps=np.full((ssp_z.size, ssp_r.size), 1500.0))


def wedge_environment() -> RamEnvironment:
    """The wedge as RAM takes it from the radial."""
    return RamEnvironment.from_radial(wedge_area(), wedge_radial(), WEDGE_SOURCE_DEPTH_M)


def munk_environment(source_depth_m: float = 100.0) -> RamEnvironment:
    """The built-in munk-1000 area as a flat RAM environment."""
    return RamEnvironment.from_area(envdata.load_area("munk-1000"), source_depth_m)


def range_average_tl_db(tl_db: np.ndarray, window: int) -> np.ndarray:
    """TL after a running intensity mean over ``window`` receivers along range (last axis),
    the ends averaged over the part of the window inside the grid; NaN stays NaN."""
    intensity = 10.0 ** (-np.asarray(tl_db, dtype=float) / 10.0)
    kernel = np.ones(window)
    valid = np.isfinite(intensity)
    filled = np.where(valid, intensity, 0.0)

    def run(values):
        return np.apply_along_axis(lambda row: np.convolve(row, kernel, mode="same"), -1, values)

    mean = run(filled) / np.maximum(run(valid.astype(float)), 1.0)
    return np.where(valid, -10.0 * np.log10(np.maximum(mean, 1e-30)), np.nan)


def write_study_file(out: Path, doc: dict) -> None:
    """Write a study script's JSON result through a temporary file (its folder made)."""
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_suffix(".tmp")
    tmp.write_text(json.dumps(doc, indent=1) + "\n")
    tmp.replace(out)
