"""Hostile inputs and outputs through the real command line (README, after the command list).

Each case: exit status 2, exactly one line on stderr starting ``error:`` (no traceback), and
nothing written or replaced.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

import acoustics
from tests.conftest import DATA, MALFORMED
from tools import cli

TINY = str(DATA / "tiny-munk.toml")


def run_cli(capsys, *argv) -> str:
    """Run ``tmakit argv`` in this process; assert the clean-error contract; return the line."""
    status = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert status == 2, (out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), err
    assert "Traceback" not in err
    return lines[0]


def listing(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}


# ------------------------------------------------------------------ inputs


@pytest.mark.parametrize("name, match", [
    ("nested-deep.toml", "TOML nested too deeply to read"),
    ("name-newline.toml", r"\[area\] name: must be letters, digits, '.', '_' or '-'"),
    ("name-quote.toml", r"\[area\] name: must be letters, digits"),
    ("band-name-space.toml", r"band name: must be letters, digits, .* got 'FB 1'"),
    ("run-timeout-negative.toml", r"\[propagation\] run_timeout_s: must be in \(0, 2592000\] s"),
])
def test_malformed_area_files_through_the_command_line(capsys, tmp_path, name, match):
    import re

    line = run_cli(capsys, "grids", "build", MALFORMED / "area" / name, "--out", tmp_path / "g.nc")
    assert re.search(match, line), line
    assert list(tmp_path.iterdir()) == []


def test_a_grid_too_large_for_the_machine_is_refused_before_it_starts(capsys, tmp_path):
    line = run_cli(capsys, "grids", "build", DATA / "huge-grid.toml",
                   "--out", tmp_path / "g.nc")
    assert "would need" in line and "GiB of memory, more than the limit" in line
    assert "--max-gib" in line
    assert list(tmp_path.iterdir()) == []


def test_max_gib_lowers_the_limit(capsys, tmp_path, monkeypatch):
    monkeypatch.delenv("TMAKIT_MAX_GIB", raising=False)
    line = run_cli(capsys, "--max-gib", "0.000001", "grids", "build", TINY, "--out", tmp_path / "g.nc")
    assert "more than the limit of 1e-06 GiB (--max-gib" in line
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("kind", ["fifo", "device", "directory"])
def test_inputs_that_are_not_regular_files(capsys, tmp_path, kind):
    if kind == "fifo":
        path = tmp_path / "area.toml"
        os.mkfifo(path)  # reading it would block forever
    elif kind == "device":
        path = Path("/dev/zero")  # reading it would never end
    else:
        path = tmp_path / "folder.toml"
        path.mkdir()
    for argv, what in ((["grids", "build", path], "area file"),
                       (["grids", "show", path], "grid file"),
                       (["locate", "--bearings", path], "bearings file")):
        line = run_cli(capsys, *argv)
        assert line.startswith(f"error: {path}: ") and what in line, line


def test_measurement_csv_that_is_a_fifo(capsys, tmp_path, tiny_grid_file):
    fifo = tmp_path / "m.csv"
    os.mkfifo(fifo)
    line = run_cli(capsys, "track", "--grid", tiny_grid_file, "--measurements", fifo,
                   "--out", tmp_path / "t.csv")
    assert "is not a regular file" in line and "measurement CSV" in line
    assert not (tmp_path / "t.csv").exists()


@pytest.mark.parametrize("name, match", [
    ("position_1e300.csv", r"row 2, column obs_x_m: 1e\+300 m is beyond 20000 km"),
    ("time_1e300.csv", r"row 2, column t_s: 1e\+300 s is beyond 100 years"),
])
def test_measurements_far_beyond_the_physical(capsys, tmp_path, tiny_grid_file, name, match):
    import re

    line = run_cli(capsys, "track", "--grid", tiny_grid_file,
                   "--measurements", MALFORMED / "measurements" / name, "--out", tmp_path / "t.csv")
    assert re.search(match, line), line
    assert not (tmp_path / "t.csv").exists()


@pytest.mark.parametrize("name, match", [
    ("cycles_too_many.toml", r"simulating 1 run\(s\) of 864000001 cycles would need [0-9.]+ GiB"),
    ("position_far.toml", r"\[target\] x_m: 1e\+300 m is beyond 20000 km of the origin"),
    ("name_slash.toml", r"\[scenario\] name: must be letters, digits"),
])
def test_scenarios_beyond_the_machine_or_the_physical(capsys, tmp_path, tiny_grid_file, name, match):
    import re

    out = tmp_path / "sim"
    line = run_cli(capsys, "simulate", MALFORMED / "scenario" / name, "--grid", tiny_grid_file,
                   "--out", out)
    assert re.search(match, line), line
    assert not out.exists() or list(out.iterdir()) == []


def _grid_with(tiny_grid, tmp_path, **attrs) -> Path:
    path = tmp_path / "bad.nc"
    acoustics.write_grid(tiny_grid.assign_attrs(**attrs), path)
    return path


@pytest.mark.parametrize("attrs, match", [
    ({"area_json": "{oops"}, "area_json: not valid JSON"),
    ({"observer_depth_m": "deep"}, "global attribute 'observer_depth_m' must be a number"),
])
def test_damaged_grids_are_refused_by_every_command(capsys, tmp_path, tiny_grid, attrs, match):
    bad = _grid_with(tiny_grid, tmp_path, **attrs)
    for argv in (["grids", "show", bad], ["grids", "plot", bad, "--out", tmp_path / "p.png"],
                 ["simulate", "gm-tv-30km", "--grid", bad, "--out", tmp_path / "sim"],
                 ["track", "--grid", bad, "--measurements", MALFORMED / "measurements" / "empty.csv",
                  "--out", tmp_path / "t.csv"]):
        line = run_cli(capsys, *argv)
        assert match in line, line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.nc"]


def test_grid_whose_area_names_other_classes(capsys, tmp_path, tiny_grid):
    data = json.loads(tiny_grid.attrs["area_json"])
    data["classes"][1]["name"] = "TANKER"
    bad = _grid_with(tiny_grid, tmp_path, area_json=json.dumps(data))
    line = run_cli(capsys, "grids", "show", bad)
    assert "class names SUB, TANKER do not match the grid's SUB, SHIP" in line


def test_grid_with_a_negative_integration_time(capsys, tmp_path, tiny_grid):
    data = json.loads(tiny_grid.attrs["area_json"])
    data["sonar"]["integration_time_s"] = -10.0
    bad = _grid_with(tiny_grid, tmp_path, area_json=json.dumps(data))
    line = run_cli(capsys, "grids", "show", bad)
    assert "[sonar] integration_time_s: must be in (0, 3600] s, got -10.0" in line


def test_all_nan_grid(capsys, tmp_path, tiny_grid):
    path = tmp_path / "nan.nc"
    acoustics.write_grid(tiny_grid.assign(k_db=tiny_grid["k_db"] * float("nan")), path)
    line = run_cli(capsys, "grids", "show", path)
    assert "variable 'k_db' holds no finite value" in line


# ------------------------------------------------------------------ outputs


def test_track_out_that_is_a_directory_or_under_a_file(capsys, tmp_path, tiny_grid_file):
    meas = tmp_path / "m.csv"
    meas.write_text("t_s,obs_x_m,obs_y_m,obs_depth_m,bearing_deg\n0,0,0,100,10\n10,50,0,100,11\n")
    folder = tmp_path / "folder"
    folder.mkdir()
    line = run_cli(capsys, "track", "--grid", tiny_grid_file, "--measurements", meas, "--out", folder)
    assert f"{folder}: is a directory" in line
    line = run_cli(capsys, "track", "--grid", tiny_grid_file, "--measurements", meas,
                   "--out", meas / "t.csv")
    assert f"{meas} is a file, not a folder" in line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["folder", "m.csv"]


def test_simulate_writes_both_files_or_neither(capsys, tmp_path, tiny_grid_file):
    out = tmp_path / "sim"
    out.mkdir()
    (out / "truth.csv").mkdir()  # truth.csv cannot be written
    line = run_cli(capsys, "simulate", "gm-tv-30km", "--grid", tiny_grid_file, "--out", out)
    assert "truth.csv: is a directory" in line
    assert sorted(p.name for p in out.iterdir()) == ["truth.csv"]


def test_output_path_that_is_not_utf8(tmp_path, tiny_grid_file):
    # a name in Latin-1 bytes: the shell passes it as is
    bad = os.fsencode(tmp_path) + b"/caf\xe9.csv"
    meas = tmp_path / "m.csv"
    meas.write_text("t_s,obs_x_m,obs_y_m,obs_depth_m,bearing_deg\n0,0,0,100,10\n10,50,0,100,11\n")
    proc = subprocess.run([sys.executable, "-m", "tools.cli", "track", "--grid", str(tiny_grid_file),
                           "--measurements", str(meas), "--out", bad],
                          capture_output=True, timeout=300)
    err = proc.stderr.decode("utf-8", "replace")
    assert proc.returncode == 2, err
    assert err.strip().count("\n") == 0 and "output path is not valid UTF-8" in err
    assert sorted(os.listdir(tmp_path)) == ["m.csv"]
def test_an_existing_file_of_another_kind_is_not_replaced(capsys, tmp_path):
    notes = tmp_path / "notes.txt"
    notes.write_text("my notes\n")
    line = run_cli(capsys, "grids", "build", TINY, "--out", notes, "--model", "urick")
    assert "exists and is not a tmakit netCDF file; not replaced (--force replaces it)" in line
    line = run_cli(capsys, "locate", "plan", "--target-x-m", "9000", "--target-y-m", "9000",
                   "--out", notes)
    assert "not a route CSV" in line
    assert notes.read_text() == "my notes\n"
    assert cli.main(["locate", "plan", "--target-x-m", "9000", "--target-y-m", "9000",
                     "--out", str(notes), "--force"]) == 0
    assert notes.read_text().startswith("t_s,obs_x_m,obs_y_m,bearing_deg")


def test_a_plot_path_that_cannot_be_written(capsys, tmp_path, tiny_grid_file):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    line = run_cli(capsys, "grids", "plot", tiny_grid_file, "--out", blocker / "p.png")
    assert "is a file, not a folder" in line
    line = run_cli(capsys, "locate", "--bearings", DATA / "locate" / "paper_pair.csv",
                   "--plot", blocker / "p.png")
    assert "is a file, not a folder" in line
    assert blocker.read_text() == "x"


def test_a_folder_where_no_file_can_be_made_is_refused_before_any_work(capsys, tmp_path, tiny_grid_file):
    # /proc (Linux, where tmakit runs) lets nobody, root included, create a file: permission
    # bits alone do not show it
    line = run_cli(capsys, "grids", "build", DATA / "tiny-munk.toml", "--out", "/proc/tmakit-test.nc")
    assert line.startswith("error: /proc/tmakit-test.nc: cannot write: cannot create a file in /proc")
    line = run_cli(capsys, "grids", "plot", tiny_grid_file, "--out", "/proc/tmakit-test.png")
    assert line.startswith("error: /proc/tmakit-test.png: cannot write")


def test_a_hung_bellhop_ends_the_build_at_its_limit(capsys, tmp_path, monkeypatch):
    import time

    # the stand-in's own command line, for pgrep: a shell comment is on no command line
    pattern = f"sleep 1000.{os.getpid()}"
    hang = tmp_path / "bellhop.sh"
    hang.write_text(f"#!/bin/sh\nexec {pattern}\n")
    hang.chmod(0o755)
    monkeypatch.setenv("BELLHOP_EXE", str(hang))
    area = tmp_path / "area.toml"
    area.write_text((DATA / "tiny-munk.toml").read_text().replace(
        "n_beams = 300", "n_beams = 300\nrun_timeout_s = 1.0"))
    out = tmp_path / "out"
    start = time.perf_counter()
    line = run_cli(capsys, "grids", "build", area, "--out", out / "g.nc", "--workers", "2")
    assert time.perf_counter() - start < 30.0
    assert "BELLHOP did not finish within 1 s and was killed" in line
    assert not (out / "g.nc").exists()
    leftovers = subprocess.run(["pgrep", "-f", pattern], capture_output=True)
    assert leftovers.returncode == 1  # no BELLHOP left running


@pytest.mark.parametrize("address", ["tls://127.0.0.1:1", "ucx://127.0.0.1:1", "inproc://x",
                                     "not a url::", "tcp://127.0.0.1:notaport", "localhost:0"])
def test_malformed_scheduler_addresses(capsys, tmp_path, address):
    line = run_cli(capsys, "grids", "build", TINY, "--out", tmp_path / "g.nc", "--scheduler", address)
    assert f"scheduler {address}" in line or f"scheduler {address!r}" in line
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("argv, message", [
    (["grids", "plot", "x.nc", "--out", "y.png", "--what", "banana"],
     "error: tmakit grids plot: argument --what: invalid choice: 'banana'"),
    (["track", "--grid"], "error: tmakit track: argument --grid: expected one argument"),
    (["nosuch"], "error: tmakit: argument COMMAND: invalid choice: 'nosuch'"),
    (["grids", "build", "ocean-deep", "--workers", "two"], "error: tmakit grids build: argument --workers: "
                                                            "invalid int value: 'two'"),
])
def test_a_malformed_command_line_is_one_error_line(capsys, argv, message):
    from tools.cli import main

    with pytest.raises(SystemExit) as exit_info:
        main(argv)
    assert exit_info.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(message), err
