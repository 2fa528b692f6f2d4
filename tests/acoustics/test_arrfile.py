"""BELLHOP's binary arrivals file (``acoustics.bellhop.arrfile``): a real arrivals run read back,
and the same file damaged in each way the reader names."""

from __future__ import annotations

import struct

import numpy as np
import pytest

from acoustics.bellhop.arrfile import read_arr
from acoustics.bellhop.envfile import env_text
from acoustics.bellhop.runner import run_env
from acoustics.builder.plan import run_spec
from acoustics.errors import BellhopError

pytestmark = pytest.mark.bellhop


@pytest.fixture(scope="module")
def arr_bytes(tiny_area, tmp_path_factory) -> bytes:
    spec = run_spec(tiny_area, title="arrivals", freq_hz=200.0, source_depths_m=(50.0,),
                    receiver_depths_m=(5.0, 10.0, 20.0), ranges_m=(1000.0, 2000.0, 3000.0), fan=(200, -60.0, 60.0),
                    arrivals=True)
    folder = tmp_path_factory.mktemp("arr")
    run_env(env_text(tiny_area, spec), keep_dir=folder)
    return (folder / "tmakit.arr").read_bytes()


def test_a_real_arrivals_file_reads_into_its_receivers(arr_bytes, tmp_path):
    path = tmp_path / "a.arr"
    path.write_bytes(arr_bytes)
    (arr,) = read_arr(path)
    assert arr.count.shape == (3, 3) and arr.count.min() >= 1
    n = int(arr.count.sum())
    assert arr.amplitude.shape == arr.receiver_angle_deg.shape == arr.surface_bounces.shape == (n,)
    assert np.all(arr.amplitude > 0) and np.all(arr.delay_s > 0.5) and np.all(np.abs(arr.receiver_angle_deg) < 90)
    np.testing.assert_allclose(arr.range_m, [1000.0, 2000.0, 3000.0])
    np.testing.assert_allclose(arr.receiver_depth_m, [5.0, 10.0, 20.0])
    # each arrival's delay is at least the straight path's at the slowest speed's bound
    r = np.repeat(np.tile(arr.range_m, 3), arr.count.ravel())
    assert np.all(arr.delay_s >= r / 1600.0)


def _first_count_record(raw: bytes) -> int:
    """Byte position of the first receiver's count record: after the header's six records."""
    pos = 0
    for _ in range(6):  # tag, frequency, sources, receiver depths, ranges, the largest count
        pos += struct.unpack_from("<i", raw, pos)[0] + 8
    return pos


@pytest.mark.parametrize(("damage", "message"), [
    ("truncate", "truncated"),
    ("count record", "a count record of 8 bytes"),
    ("arrival record", r"damaged \(receiver 0\)"),
])
def test_a_damaged_arrivals_file_is_a_bellhop_error(arr_bytes, tmp_path, damage, message):
    raw = bytearray(arr_bytes)
    pos = _first_count_record(bytes(raw))
    if damage == "truncate":
        raw = raw[:len(raw) - 100]
    elif damage == "count record":
        struct.pack_into("<i", raw, pos, 8)
    else:
        struct.pack_into("<i", raw, pos + 12, 7)  # the first arrival's leading byte count
    path = tmp_path / "bad.arr"
    path.write_bytes(bytes(raw))
    with pytest.raises(BellhopError, match=message):
        read_arr(path)
