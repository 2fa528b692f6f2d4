"""The tmakit command line: doctor, areas, grids build/show/plot, errors, reuse and resume."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import acoustics
from tests.conftest import DATA, MALFORMED
from tools.cli import main

REPO = Path(__file__).resolve().parents[2]


def tmakit(*args: str, env: dict | None = None, **kw) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "tools.cli", *args], capture_output=True, text=True,
                          cwd=REPO, env={**os.environ, **(env or {})}, **kw)


def json_out(capsys, argv) -> dict:
    assert main([*argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.bellhop
def test_doctor_reports_the_binary_and_a_working_tiny_run(capsys):
    data = json_out(capsys, ["doctor"])
    assert data["bellhop"]["found_by"] in ("install", "BELLHOP_EXE", "PATH")
    assert Path(data["bellhop"]["path"]).is_file()
    assert data["self_test"]["ok"] is True
    assert abs(data["self_test"]["tl_db_at_100m"] - 40.0) < 1.0  # spherical spreading at 100 m


def test_doctor_without_bellhop_is_one_error_line():
    proc = tmakit("doctor", env={"BELLHOP_EXE": "/no/such/bellhop.exe"})
    assert proc.returncode == 2
    assert proc.stderr.strip() == "error: BELLHOP_EXE=/no/such/bellhop.exe: not an executable file"
    assert "Traceback" not in proc.stderr


def test_areas_list_and_show(capsys):
    data = json_out(capsys, ["areas", "list"])
    names = [a["name"] for a in data["areas"]]
    assert "ocean-deep" in names and "munk-1000" in names
    assert [a["name"] for a in data["areas"] if a["default"]] == ["ocean-deep"]
    shown = json_out(capsys, ["areas", "show", "munk-1000"])
    assert shown["water"]["depth_m"] == 1000.0 and shown["observer"]["depth_m"] == 300.0
    assert main(["areas", "show", "ocean-deep"]) == 0
    assert "NPS: depth 200 m" in capsys.readouterr().out


@pytest.mark.parametrize("name", ["negative-depth.toml", "syntax-error.toml", "binary.toml"])
def test_bad_area_is_one_error_line_and_writes_nothing(tmp_path, name):
    out = tmp_path / "g.nc"
    proc = tmakit("grids", "build", str(MALFORMED / "area" / name), "--out", str(out))
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"error: {MALFORMED / 'area' / name}: ")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.bellhop
def test_build_show_plot_and_reuse(capsys, tmp_path, tiny_area_path, tiny_grid):
    out = tmp_path / "tiny.nc"
    built = json_out(capsys, ["grids", "build", str(tiny_area_path), "--out", str(out), "--workers", "2"])
    assert built["up_to_date"] is False and built["runs"] == 4 and built["runs_reused"] == 0
    xr.testing.assert_identical(acoustics.open_tables(out).dataset.drop_attrs(), tiny_grid.drop_attrs())
    assert not any(p.name.startswith(".") for p in tmp_path.iterdir())  # cache removed

    again = json_out(capsys, ["grids", "build", str(tiny_area_path), "--out", str(out)])
    assert again["up_to_date"] is True and again["runs"] == 0
    forced = json_out(capsys, ["grids", "build", str(tiny_area_path), "--out", str(out), "--force"])
    assert forced["up_to_date"] is False and forced["runs"] == 4

    shown = json_out(capsys, ["grids", "show", str(out)])
    assert shown["classes"] == ["SUB", "SHIP"] and shown["dims"]["range"] == 50
    assert main(["grids", "show", str(out)]) == 0
    assert "K(r) dB at 1 km" in capsys.readouterr().out

    png = tmp_path / "tiny.png"
    assert main(["grids", "plot", str(out), "--out", str(png), "--class", "SHIP"]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 20_000
    capsys.readouterr()
    assert main(["grids", "plot", str(out), "--out", str(tmp_path / "x.png"), "--class", "NOPE"]) == 2
    assert "class 'NOPE' is not a class of the grid" in capsys.readouterr().err
    assert not (tmp_path / "x.png").exists()


def test_urick_build_needs_no_bellhop(capsys, tmp_path, tiny_area_path):
    out = tmp_path / "u.nc"
    data = json_out(capsys, ["grids", "build", str(tiny_area_path), "--out", str(out), "--model", "urick"])
    assert data["runs"] == 0
    ds = acoustics.open_tables(out).dataset
    np.testing.assert_array_equal(ds["k_db"].values, ds["k_urick_db"].values)


def test_show_of_a_bad_grid_file_is_one_error_line(capsys):
    path = MALFORMED / "grid" / "not-netcdf.nc"
    assert main(["grids", "show", str(path)]) == 2
    assert capsys.readouterr().err.strip() == f"error: {path}: not a netCDF file"


def default_sigint() -> None:
    """In the child: SIGINT back to its default, whatever this test run inherited (a
    background job starts with SIGINT ignored, and Python then installs no handler)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@pytest.mark.bellhop
@pytest.mark.slow
@pytest.mark.parametrize("signum, status", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_interrupted_build_leaves_no_file_and_resumes(tmp_path, tiny_area_path, signum, status):
    area_text = tiny_area_path.read_text().replace("n_beams = 300", "n_beams = 4000\nfrequency_shortcut = false")
    area_file = tmp_path / "slow.toml"
    area_file.write_text(area_text)
    out = tmp_path / "slow.nc"
    proc = subprocess.Popen([sys.executable, "-m", "tools.cli", "grids", "build", str(area_file), "--out", str(out),
                             "--workers", "1"], cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=default_sigint)
    deadline = time.time() + 60
    cache = None
    while time.time() < deadline:
        caches = [p for p in tmp_path.iterdir() if p.name.startswith(".slow.nc.partial")]
        if caches and len(list(caches[0].glob("*.npy"))) >= 3:
            cache = caches[0]
            break
        time.sleep(0.02)
    assert cache is not None, "the build never wrote a finished run"
    proc.send_signal(signum)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == status, err
    assert err.strip().splitlines()[-1].startswith("error: interrupted")
    assert not out.exists()
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".tmp")]
    done_before = len(list(cache.glob("*.npy")))
    assert 3 <= done_before < 16  # 2 depths x (7 + 1) frequencies

    resumed = tmakit("grids", "build", str(area_file), "--out", str(out), "--workers", "2", "--json")
    assert resumed.returncode == 0, resumed.stderr
    info = json.loads(resumed.stdout)
    assert info["runs"] == 16 and info["runs_reused"] == done_before
    assert out.exists() and not cache.exists()


@pytest.mark.parametrize("workers", [1, 2])
@pytest.mark.parametrize("signum, status", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_an_interrupt_kills_the_runs_under_way_and_starts_no_more(tmp_path, signum, status, workers):
    # BELLHOP stands in as a process that never ends: an interrupt must not wait for it, nor for
    # a run a worker thread starts behind it once its slot is free (each worker's second thread
    # waits for the slot with the next run's files written)
    pattern = f"sleep 1000.{os.getpid()}{signum}{workers}"  # this test's own, for pgrep
    hang = tmp_path / "bellhop.sh"
    hang.write_text(f"#!/bin/sh\nexec {pattern}\n")
    hang.chmod(0o755)
    out = tmp_path / "g.nc"
    proc = subprocess.Popen([sys.executable, "-m", "tools.cli", "grids", "build", str(DATA / "tiny-munk.toml"),
                             "--out", str(out), "--workers", str(workers)], cwd=REPO,
                            env={**os.environ, "BELLHOP_EXE": str(hang)}, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, preexec_fn=default_sigint)
    deadline = time.time() + 60
    while time.time() < deadline:
        found = subprocess.run(["pgrep", "-f", pattern], capture_output=True, text=True).stdout.split()
        if len(found) >= workers:
            break
        time.sleep(0.05)
    assert len(found) >= workers, "the build never started its runs"
    start = time.perf_counter()
    proc.send_signal(signum)
    _, err = proc.communicate(timeout=60)
    assert time.perf_counter() - start < 10.0  # the runs take 1000 s: nothing waited for them
    assert proc.returncode == status, err
    assert err.strip().splitlines()[-1].startswith("error: interrupted")
    assert not out.exists()
    assert subprocess.run(["pgrep", "-f", pattern], capture_output=True).returncode == 1  # none left


@pytest.mark.parametrize("argv", [["--json", "areas", "list"], ["areas", "--json", "list"],
                                  ["areas", "list", "--json"]])
def test_json_option_works_at_any_position(capsys, argv):
    assert main(argv) == 0
    assert "areas" in json.loads(capsys.readouterr().out)


def test_grids_compare_through_the_command_line(tiny_grid_file, tmp_path, capsys):
    """`tmakit grids compare` reports by class and band, writes its picture, and refuses two
    grids of different areas with one error line and no picture."""
    urick = tmp_path / "tiny-urick.nc"
    assert main(["grids", "build", str(DATA / "tiny-munk.toml"), "--model", "urick", "--out", str(urick)]) == 0
    capsys.readouterr()
    png = tmp_path / "diff.png"
    assert main(["grids", "compare", str(urick), str(tiny_grid_file), "--plot", str(png), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert {(r["class"], r["band"]) for r in data["rows"]} == {(c, b) for c in ("SUB", "SHIP") for b in ("FB1", "F500")}
    # BELLHOP against spherical spreading over 1000 m of Munk water: a few dB, not 0, not 50
    assert all(0.5 < r["tl_median_db"] < 10.0 for r in data["rows"])
    other = tmp_path / "munk-urick.nc"
    assert main(["grids", "build", "munk-1000", "--model", "urick", "--out", str(other)]) == 0
    capsys.readouterr()
    bad_png = tmp_path / "bad.png"
    assert main(["grids", "compare", str(urick), str(other), "--plot", str(bad_png)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "area 'tiny-munk' against 'munk-1000'" in err[0] and err[0].startswith("error:")
    assert not bad_png.exists()


@pytest.mark.bellhop
def test_grids_check_reports_each_doubling_and_the_build_settings(capsys, tmp_path):
    from tests.conftest import DATA

    assert main(["grids", "check", str(DATA / "tiny-munk.toml"), "--workers", "2", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    names = [v["name"] for v in out["variants"]]
    assert names == ["beams", "ray_step", "freqs_per_band", "one_run_per_band"]
    assert out["settings"]["n_beams"] == 300 and out["settings"]["mode"] == "semicoherent"
    assert out["settings"]["surface_image_beams"] == 3000
    for v in out["variants"]:
        assert v["median_db"] >= 0.0 and v["worst_db"] >= v["median_db"] - 1e-9
        assert v["converged"] == (v["median_db"] <= 0.2)
    # the tiny area (5 km, 1000 m) is converged with 300 beams (0.05 dB at worst, measured);
    # with 40 the doubling moves K by far more than 0.2 dB
    assert out["converged"]
    few = tmp_path / "few-beams.toml"
    few.write_text((DATA / "tiny-munk.toml").read_text().replace("n_beams = 300", "n_beams = 40"))
    assert main(["grids", "check", str(few)]) == 0
    text = capsys.readouterr().out
    assert "n_beams 40 -> 80: K moves" in text and "NOT converged" in text


def test_grids_check_of_a_missing_area_is_one_error_line(capsys, tmp_path):
    assert main(["grids", "check", str(tmp_path / "nope.toml")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error:")
    assert main(["grids", "check", str(tmp_path / "nope.toml"), "--workers", "0"]) == 2
