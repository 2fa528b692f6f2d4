"""Measurement CSV: round trip and one malformed file per error message."""

from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tracker.errors import MeasurementFileError
from tracker.measurements import Measurements, read_measurements, write_measurements
from tracker.trackfile import TRACK_COLUMNS, read_track, write_track

BAD = Path(__file__).parent.parent / "data" / "malformed" / "measurements"


def _m():
    return Measurements(source="x", t_s=[0.0, 10.0, 20.0], obs_x_m=[0.0, 25.0, 50.0],
                        obs_y_m=[0.0, 0.0, 0.0], obs_depth_m=[100.0] * 3,
                        bearing_deg=[10.0, np.nan, 11.0], bearing_sigma_deg=[0.2, np.nan, 0.2],
                        band_names=("FB1", "FB2"), level_db=[[80.0, np.nan]] * 3,
                        snr_db=[[3.0, np.nan]] * 3)


def test_round_trip_keeps_blanks_and_velocity(tmp_path):
    path = tmp_path / "m.csv"
    write_measurements(path, _m())
    m = read_measurements(path, ["FB1", "FB2", "FB3"])
    assert m.band_names == ("FB1", "FB2")
    assert np.isnan(m.bearing_deg[1]) and np.isnan(m.level_db[0, 1])
    assert_allclose(m.level_db[:, 0], 80.0)
    vx, vy = m.obs_velocity_mps()
    assert_allclose(vx, 2.5)
    assert_allclose(vy, 0.0)


@pytest.mark.parametrize("name, match", [
    ("missing_bearing.csv", "missing required column 'bearing_deg'"),
    ("nonnumeric_bearing.csv", r"row 1 .*column bearing_deg: 'abc' is not a number"),
    ("bearing_out_of_range.csv", r"bearing_deg: 360.5 deg is outside \[0, 360\)"),
    ("time_not_increasing.csv", r"row 2 .*column t_s: 0 s is not after"),
    ("unknown_band.csv", r"column 'level_db_FB9': band 'FB9' is not a band of the grid"),
    ("level_out_of_range.csv", r"level_db_FB1: 900 dB is outside"),
    ("empty.csv", "empty file"),
    ("no_rows.csv", "no data rows"),
])
def test_malformed_measurements(name, match):
    with pytest.raises(MeasurementFileError, match=match) as info:
        read_measurements(BAD / name, ["FB1", "FB2", "FB3"])
    assert name in str(info.value)


def test_write_track_checks_columns(tmp_path):
    import pandas as pd

    df = pd.DataFrame({c: [1.0] for c in TRACK_COLUMNS})
    df["class"], df["method"], df["tack"] = "TV", "ml", 1
    write_track(tmp_path / "t.csv", df)
    assert list(read_track(tmp_path / "t.csv").columns) == list(TRACK_COLUMNS)
    with pytest.raises(ValueError, match="lacks column 'range_m'"):
        write_track(tmp_path / "u.csv", df.drop(columns="range_m"))
    assert not (tmp_path / "u.csv").exists()
