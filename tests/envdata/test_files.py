"""Input gate and all-or-none writes of several files."""

from __future__ import annotations

import os

import pytest

from envdata.errors import InputError
from envdata.files import atomic_paths, check_input_file, read_input_bytes


def test_several_files_are_all_written_or_none(tmp_path):
    (tmp_path / "a.csv").write_text("old a")
    with atomic_paths([tmp_path / "a.csv", tmp_path / "b.csv"]) as (ta, tb):
        ta.write_text("new a")
        tb.write_text("new b")
    assert (tmp_path / "a.csv").read_text() == "new a" and (tmp_path / "b.csv").read_text() == "new b"
    # the second rename fails (b is now a folder): a goes back to what it was
    (tmp_path / "b.csv").unlink()
    (tmp_path / "b.csv").mkdir()
    with pytest.raises(OSError):
        with atomic_paths([tmp_path / "a.csv", tmp_path / "b.csv"]) as (ta, tb):
            ta.write_text("newer a")
            tb.write_text("newer b")
    assert (tmp_path / "a.csv").read_text() == "new a"
    assert sorted(os.listdir(tmp_path)) == ["a.csv", "b.csv"]  # no temporary or kept-aside file


def test_an_interrupted_write_leaves_nothing(tmp_path):
    with pytest.raises(KeyboardInterrupt):
        with atomic_paths([tmp_path / "a.nc", tmp_path / "b.png"]) as (ta, tb):
            ta.write_text("partial")
            raise KeyboardInterrupt
    assert os.listdir(tmp_path) == []


def test_inputs_must_be_regular_files(tmp_path):
    fifo = tmp_path / "f"
    os.mkfifo(fifo)
    with pytest.raises(InputError, match=r"f: is not a regular file \(a FIFO, device or socket\), not an area file"):
        check_input_file(fifo, "area file")
    with pytest.raises(InputError, match=r"is a directory, not a grid file"):
        check_input_file(tmp_path, "grid file")
    with pytest.raises(InputError, match=r"nope: measurement CSV not found"):
        check_input_file(tmp_path / "nope", "measurement CSV")
    with pytest.raises(InputError, match=r"not found \(a folder on its path is a file\)"):
        (tmp_path / "plain").write_text("x")
        check_input_file(tmp_path / "plain" / "inside", "area file")


def test_inputs_larger_than_read_whole_are_refused(tmp_path):
    big = tmp_path / "big.csv"
    big.write_bytes(b"x" * 2048)
    assert read_input_bytes(big, "bearings file", max_bytes=4096) == b"x" * 2048
    with pytest.raises(InputError, match=r"big.csv: bearings file is larger than the 0.000977 MiB tmakit reads"):
        read_input_bytes(big, "bearings file", max_bytes=1024)
