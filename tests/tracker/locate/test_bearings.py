"""The Bearings input and the bearings CSV: validation and one error per malformed file."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tests.conftest import DATA
from tests.tracker.locate.conftest import MALFORMED
from tracker import locate as loc
from tracker.errors import LocateError, MeasurementFileError


def test_bearings_from_arrays_are_validated():
    with pytest.raises(LocateError, match=r"row 2: -5.0 deg is outside \[0, 360\) deg"):
        loc.Bearings.from_arrays([0.0, 1.0], [0.0, 0.0], [45.0, -5.0])
    with pytest.raises(LocateError, match=r"row 1: nan m is not a finite number"):
        loc.Bearings.from_arrays([math.nan, 1.0], [0.0, 0.0], [45.0, 30.0])
    with pytest.raises(LocateError, match="differ in length"):
        loc.Bearings.from_arrays([0.0, 1.0], [0.0], [45.0, 30.0])
    with pytest.raises(LocateError, match="method: must be one of"):
        loc.locate(loc.Bearings.from_arrays([0.0, 1.0], [0.0, 0.0], [45.0, 30.0]), method="x")


def test_read_bearings_ignores_extra_columns_in_any_order():
    b = loc.read_bearings_csv(DATA / "locate" / "six_bearings_extra_columns.csv")
    assert len(b) == 6
    assert_allclose(b.t_s, np.arange(6) * 60.0)
    fix = loc.locate(b, method="lsq")
    # the file holds bearings to (-4000, 7500) m rounded to 12 digits
    assert_allclose([fix.x_m, fix.y_m], [-4000.0, 7500.0], atol=1e-3)
    assert list(b.to_frame().columns) == list(loc.BEARING_COLUMNS)


MALFORMED_CASES = [
    ("empty.csv", MeasurementFileError, r"empty\.csv: the file is empty"),
    ("binary.csv", MeasurementFileError, r"binary\.csv: not a text CSV file \(binary data"),
    ("not_utf8.csv", MeasurementFileError, r"not_utf8\.csv: not a text CSV file \(not UTF-8"),
    ("header_only.csv", MeasurementFileError, r"header_only\.csv: no data rows"),
    ("missing_column.csv", MeasurementFileError,
     r"missing_column\.csv: missing column 'bearing_deg'"),
    ("non_numeric.csv", MeasurementFileError,
     r"non_numeric\.csv: row 2 \(line 3\), column obs_x_m: 'east' is not a number \(m\)"),
    ("blank_value.csv", MeasurementFileError,
     r"blank_value\.csv: row 2 \(line 3\), column bearing_deg: blank value"),
    ("nan_bearing.csv", MeasurementFileError,
     r"nan_bearing\.csv: row 2 \(line 3\), column bearing_deg: nan deg is not a finite number"),
    ("bearing_out_of_range.csv", MeasurementFileError,
     r"bearing_out_of_range\.csv: row 2 \(line 3\), column bearing_deg: 360 deg is outside "
     r"\[0, 360\) deg"),
    ("ragged_row.csv", MeasurementFileError,
     r"ragged_row\.csv: row 2 \(line 3\): has 3 fields, the header has 4"),
    ("time_not_increasing.csv", MeasurementFileError,
     r"time_not_increasing\.csv: row 2 \(line 3\), column t_s: 0 s is not after the previous "
     r"row's 600 s"),
]


@pytest.mark.parametrize(("name", "error", "match"), MALFORMED_CASES)
def test_malformed_bearing_files_raise(name, error, match):
    with pytest.raises(error, match=match) as info:
        loc.read_bearings_csv(MALFORMED / name)
    assert "\n" not in str(info.value)


def test_missing_bearing_file_raises():
    with pytest.raises(MeasurementFileError, match=r"no_such\.csv: bearings file not found"):
        loc.read_bearings_csv(MALFORMED / "no_such.csv")
