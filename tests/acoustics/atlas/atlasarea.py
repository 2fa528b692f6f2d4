"""The small atlas area the atlas tests build: the shelf-break relief, 12 synthetic months.

A 3 x 3 lattice about the built-in shelf-break origin whose northern row lies on the shelf
near the coast (water shallower than the observer there: left out), 4 radials to 10 km, one
band, one class (TV at 8 m), a 50 m TL depth axis and 300 beams: one BELLHOP run per radial,
about 10-30 ms each.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import envdata
from tests.fixtures.sample_data import DATA, RELIEF_FILE, write_monthly

ATLAS_TOML = """
[area]
name = "atlas-test"
description = "shelf-break relief, 3 x 3 lattice, two months"

[origin]
lat_deg = 43.0
lon_deg = 5.0

[bearings]
step_deg = 90.0

[atlas]
lat_deg = [42.975, 43.15]
lon_deg = [4.90, 5.10]
spacing_km = {spacing_km}
months = {months}
depth_step_m = 50.0

[water]
bathymetry = "{relief}"
temperature = "woa_monthly_t.nc"
salinity = "woa_monthly_s.nc"
month = 8

[bottom]
speed_mps = 1600.0
density_gcc = 1.8
attenuation_db_per_wavelength = 0.8

[noise]
spectrum_level_1khz_db = 57.02
slope_db_per_octave = -5.0

[observer]
depth_m = 100.0

[sonar]
beamwidth_deg = 5.0
directivity_index_db = 42.0
integration_time_s = 10.0
detection_threshold = 5.0

[[bands]]
name = "FB2"
low_hz = 300.0
high_hz = 1000.0

[[classes]]
name = "TV"
depth_m = 8.0
speed_mean_mps = 7.5
speed_sd_mps = 1.0
noise_mean_db = 133.02
noise_sd_db = 2.5

[grid]
range_max_m = 10000.0
range_step_m = 200.0
depth_step_m = 25.0

[propagation]
n_beams = 300
step_m = 50.0
"""


def write_atlas_area(folder: Path, *, months=(2, 8), spacing_km: float = 8.0) -> Path:
    """The test atlas area in ``folder`` (its 12-month climatology written beside it)."""
    folder.mkdir(parents=True, exist_ok=True)
    if not (folder / "woa_monthly_t.nc").exists():
        write_monthly(folder, stem="woa_monthly")
    relief = folder / RELIEF_FILE
    if not relief.exists():
        shutil.copy(DATA / RELIEF_FILE, relief)
    path = folder / "atlas-test.toml"
    path.write_text(ATLAS_TOML.format(spacing_km=spacing_km, months=list(months), relief=RELIEF_FILE))
    return path


def load_atlas_area(folder: Path, **kwargs) -> envdata.Area:
    return envdata.load_area(write_atlas_area(folder, **kwargs))
