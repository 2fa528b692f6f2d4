"""The RAM test environments shared by the tests and the study scripts.

- Pekeris: 100 m of 1500 m/s water over a 1800 m/s, 1.8 g/cm3 lossless fluid half-space.
- ASA wedge (Jensen & Ferla 1990, the upslope benchmark): 25 Hz, source at 100 m, the bottom
  from 200 m at the source to the shore at 4 km, 1500 m/s water over 1700 m/s, 1.5 g/cm3,
  0.5 dB/wavelength, no volume absorption. Built as an ``envdata.Radial`` (flat 200 m behind
  the source, the shore at 4 km with the radials' 1 m of water) so that RAM and BELLHOP take it
  the way the bearing-dependent grid does: ``RamEnvironment.from_radial`` and
  ``acoustics.bellhop.radialfiles.radial_files``.
- RAM 1.5's own test case (M. D. Collins): 50 Hz, source and receiver at 50 m, a profile
  1480/1520/1530 m/s at 0/100/400 m that becomes 1530 m/s throughout at 25 km (RAM changes
  profiles at their ranges, no blending: given as two columns 1 m apart), the bottom sloping
  from 200 m at the source to 400 m at 40 km (then flat), a 1700 m/s, 1.5 g/cm3,
  0.5 dB/wavelength half-space; dr = 500 m, dz = 2 m, 8 Pade terms, one stability constraint,
  c0 = 1600 m/s. Its reference is the Fortran RAM's TL line (100 ranges to 50 km), which pyram
  1.3.0 ships as pyram/Tests/tl_ref.line, read from .venv-ref (``make test`` makes it and sets
  RAM_REF_PYTHON), not copied here.
- Deep: the built-in ``munk-1000`` area (1000 m of Munk water over 1600 m/s, 1.8 g/cm3,
  0.8 dB/wavelength), as ``RamEnvironment.from_area``.
"""

from __future__ import annotations

import dataclasses
import json
import subprocess
from pathlib import Path

import numpy as np

import envdata
from acoustics.ram import RamEnvironment, RamSettings
from bench.crosscheck.sidevenv import CrosscheckError, side_python
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


RAM15_FREQ_HZ = 50.0
RAM15_DEPTH_M = 50.0


def ram15_case() -> tuple[RamEnvironment, RamSettings]:
    """RAM 1.5's test case (module docstring): the environment and the settings it runs with."""
    upper, lower = [1480.0, 1520.0, 1530.0], [1530.0, 1530.0, 1530.0]
    env = RamEnvironment(bathymetry_range_m=[0.0, 40_000.0], bathymetry_depth_m=[200.0, 400.0],
                         ssp_range_m=[0.0, 24_999.0, 25_000.0], ssp_depth_m=[0.0, 100.0, 400.0],
                         speed_mps=[upper, upper, lower],
                         bottom=Bottom(speed_mps=1700.0, density_gcc=1.5, attenuation_db_per_wavelength=0.5),
                         source_depth_m=RAM15_DEPTH_M)
    layer_m = 20.0 * 1600.0 / RAM15_FREQ_HZ  # RAM 1.5's absorbing layer as pyram sets it: 20 wavelengths at c0
    settings = RamSettings(range_step_m=500.0, depth_step_m=2.0, grid_depth_m=400.0 + layer_m,
                           absorbing_layer_m=layer_m, pade_terms=8, stability_terms=1, reference_speed_mps=1600.0)
    return env, settings


def ram15_reference_path() -> Path:
    """pyram 1.3.0's tl_ref.line in .venv-ref; `CrosscheckError` when it is not there."""
    python = side_python("RAM_REF_PYTHON", ".venv-ref", "pyram 1.3.0")
    # find_spec locates the package without importing it (pyram is installed without numba)
    proc = subprocess.run([python, "-c", "import importlib.util as u; "
                           "print(u.find_spec('pyram').submodule_search_locations[0])"],
                          capture_output=True, text=True, timeout=60)
    if proc.returncode != 0:
        raise CrosscheckError(f"{python} cannot find pyram: {proc.stderr.strip()[-500:]}")
    path = Path(proc.stdout.strip()) / "Tests" / "tl_ref.line"
    if not path.is_file():
        raise CrosscheckError(f"{path} is missing from pyram in .venv-ref")
    return path


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
