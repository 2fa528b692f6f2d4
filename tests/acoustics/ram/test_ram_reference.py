"""The RAM 1.5 test case against the Fortran RAM's own TL line.

The test case that comes with RAM 1.5 (M. D. Collins): 50 Hz, source and receiver at 50 m,
a profile 1480/1520/1530 m/s at 0/100/400 m that becomes 1530 m/s throughout at 25 km (RAM
changes profiles at their ranges, no blending: given here as two columns 1 m apart), the
bottom sloping from 200 m at the source to 400 m at 40 km (then flat), a 1700 m/s, 1.5 g/cm3,
0.5 dB/wavelength half-space; dr = 500 m, dz = 2 m, 8 Pade terms, one stability constraint,
c0 = 1600 m/s, to 50 km. The reference is the Fortran RAM's TL line (100 ranges), which pyram
1.3.0 ships as pyram/Tests/tl_ref.line; it is read from .venv-ref (``make test`` makes it and
sets RAM_REF_PYTHON), not copied here.

Agreement: mean |dTL| <= 0.01 dB (the tolerance pyram itself holds to this file) and every
range within 0.05 dB; measured 0.0008 dB mean, 0.007 dB at worst.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np
import pytest

from acoustics.ram import RamEnvironment, RamSettings, ram_tl_db
from bench.crosscheck.sidevenv import side_python
from envdata.bottom import Bottom


def reference_line_path() -> Path:
    """pyram 1.3.0's tl_ref.line in .venv-ref; a failure (not a skip) when it is not there."""
    python = side_python("RAM_REF_PYTHON", ".venv-ref", "pyram 1.3.0")
    # find_spec locates the package without importing it (pyram is installed without numba)
    proc = subprocess.run([python, "-c", "import importlib.util as u; "
                           "print(u.find_spec('pyram').submodule_search_locations[0])"],
                          capture_output=True, text=True, timeout=60)
    if proc.returncode != 0:
        pytest.fail(f"{python} cannot find pyram: {proc.stderr.strip()[-500:]}", pytrace=False)
    path = Path(proc.stdout.strip()) / "Tests" / "tl_ref.line"
    if not path.is_file():
        pytest.fail(f"{path} is missing from pyram in .venv-ref", pytrace=False)
    return path


def test_ram_1_5_test_case_matches_the_fortran_tl_line():
    ref = np.loadtxt(reference_line_path())
    ref_range_m, ref_tl_db = ref[:, 0], ref[:, 1]
    assert ref.shape == (100, 2)
    upper = [1480.0, 1520.0, 1530.0]
    lower = [1530.0, 1530.0, 1530.0]
    env = RamEnvironment(bathymetry_range_m=[0.0, 40_000.0], bathymetry_depth_m=[200.0, 400.0],
                         ssp_range_m=[0.0, 24_999.0, 25_000.0], ssp_depth_m=[0.0, 100.0, 400.0],
                         speed_mps=[upper, upper, lower],
                         bottom=Bottom(speed_mps=1700.0, density_gcc=1.5, attenuation_db_per_wavelength=0.5),
                         source_depth_m=50.0)
    wavelength_m = 1600.0 / 50.0
    layer_m = 20.0 * wavelength_m  # RAM 1.5's absorbing layer as pyram sets it
    settings = RamSettings(range_step_m=500.0, depth_step_m=2.0, grid_depth_m=400.0 + layer_m,
                           absorbing_layer_m=layer_m, pade_terms=8, stability_terms=1,
                           reference_speed_mps=1600.0)
    tl = ram_tl_db(env, 50.0, [50.0], ref_range_m, settings)[0]
    diff = np.abs(tl - ref_tl_db)
    assert np.mean(diff) <= 0.01, np.mean(diff)
    assert np.max(diff) <= 0.05, np.max(diff)
