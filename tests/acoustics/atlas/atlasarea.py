"""The small atlas area the atlas tests build (tests/data/atlas-test.toml): the shelf-break relief,
12 synthetic months beside it."""

from __future__ import annotations

import shutil
from pathlib import Path

import envdata
from tests.fixtures.sample_data import DATA, RELIEF_FILE, write_monthly

ATLAS_TOML = Path(__file__).resolve().parents[2] / "data" / "atlas-test.toml"


def atlas_area_text(*, months=(2, 8), spacing_km: float = 8.0) -> str:
    """The test atlas area's TOML with another lattice spacing and other months."""
    text = ATLAS_TOML.read_text()
    return text.replace("spacing_km = 8.0", f"spacing_km = {spacing_km}").replace(
        "months = [2, 8]", f"months = {list(months)}")


def write_atlas_area(folder: Path, *, months=(2, 8), spacing_km: float = 8.0) -> Path:
    """The test atlas area in ``folder`` (its 12-month climatology written beside it)."""
    folder.mkdir(parents=True, exist_ok=True)
    if not (folder / "woa_monthly_t.nc").exists():
        write_monthly(folder, stem="woa_monthly")
    relief = folder / RELIEF_FILE
    if not relief.exists():
        shutil.copy(DATA / RELIEF_FILE, relief)
    path = folder / "atlas-test.toml"
    path.write_text(atlas_area_text(months=months, spacing_km=spacing_km))
    return path


def load_atlas_area(folder: Path, **kwargs) -> envdata.Area:
    return envdata.load_area(write_atlas_area(folder, **kwargs))
