"""tmakit track --target-depth through the command line, the good and the hostile."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest
import xarray as xr

from tools.cli import main
from tracker.trackfile import TRACK_COLUMNS

BAD = Path(__file__).parent.parent / "data" / "malformed"
pytestmark = pytest.mark.bellhop


@pytest.fixture(scope="module")
def measured(tiny_depth_grid_file, tmp_path_factory):
    """A SUB (tables at 150 m) simulated at 8 m on the tiny grid."""
    out = tmp_path_factory.mktemp("depth-cli")
    sc = out / "sc.toml"
    sc.write_text((BAD / "scenario" / "unknown_key.toml").read_text()
                  .replace('colour = "red"', "").replace('"TV"', '"SUB"')
                  .replace("130.0", "150.0").replace("10000.0", "3000.0"))
    assert main(["simulate", str(sc), "--grid", str(tiny_depth_grid_file), "--out", str(out / "sim")]) == 0
    return out / "sim" / "measurements.csv"


@pytest.mark.parametrize("method", ["rpf", "ml"])
def test_track_with_the_depth_unknown(tiny_depth_grid_file, measured, tmp_path, capsys, method):
    out = tmp_path / "track.csv"
    assert main(["track", "--grid", str(tiny_depth_grid_file), "--measurements", str(measured), "--out",
                 str(out), "--method", method, "--class", "SUB", "--target-depth", "unknown"]) == 0
    text = capsys.readouterr().out
    df = pd.read_csv(out)
    assert tuple(df.columns) == TRACK_COLUMNS
    lo, hi = 0.0, 1000.0  # SUB has no depth_range_m: the tiny grid's water column
    assert df["depth_m"].between(lo, hi).all() and (df["depth_sd_m"] >= 0).all()
    assert "depth" in text
    # both trackers weigh depth hypotheses (the particle filter as a bank, one filter each) and
    # print the posterior: the hypotheses' weights, its median (the rows' last depth), the 90 %
    # interval around it
    assert "most likely depth" in text and "ln likelihood ratio" in text and "weights: " in text
    line = next(x for x in text.splitlines() if "most likely depth" in x)
    median = float(line.split("); depth ")[1].split(" m,")[0])
    assert median == pytest.approx(df["depth_m"].iloc[-1], abs=0.5)
    lo90, hi90 = (float(v) for v in line.split("90 % in ")[1].split(" m,")[0].split("-"))
    assert lo90 <= median <= hi90 and "P(<= 15 m)" in line


def test_track_at_a_given_depth_and_at_the_class_depth(tiny_depth_grid_file, measured, tmp_path):
    for depth, expect in (("8", 8.0), ("class", 150.0)):
        out = tmp_path / f"{depth}.csv"
        assert main(["track", "--grid", str(tiny_depth_grid_file), "--measurements", str(measured),
                     "--out", str(out), "--class", "SUB", "--target-depth", depth]) == 0
        df = pd.read_csv(out)
        assert (df["depth_m"] == expect).all() and df["depth_sd_m"].isna().all()


@pytest.mark.parametrize("args, message", [
    (["--target-depth", "banana"], "target depth: 'banana' is not a depth in metres"),
    (["--target-depth", "-5"], "target depth: must be a depth >= 0 m"),
    (["--target-depth", "nan"], "target depth: must be a depth >= 0 m"),
    (["--target-depth", "5000"], "depth 5000 m is outside the grid's depth axis"),
    (["--target-depth", "unknown", "--method", "rpf-bot"], "bearings alone say nothing of the depth"),
])
def test_hostile_target_depths(tiny_depth_grid_file, measured, tmp_path, capsys, args, message):
    out = tmp_path / "t.csv"
    assert main(["track", "--grid", str(tiny_depth_grid_file), "--measurements", str(measured), "--out",
                 str(out), *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error:") and message in err[0], err
    assert not out.exists()


def test_an_old_flat_grid_is_refused_for_an_unknown_depth(tiny_depth_grid_file, measured, tmp_path, capsys):
    old = tmp_path / "old.nc"
    with xr.open_dataset(tiny_depth_grid_file) as ds:
        ds.drop_vars("tl_obs_db").load().to_netcdf(old)
    out = tmp_path / "t.csv"
    assert main(["track", "--grid", str(old), "--measurements", str(measured), "--out", str(out),
                 "--method", "rpf", "--target-depth", "unknown"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no TL from the observer depth" in err[0]
    assert "give the class a depth_range_m" in err[0] and not out.exists()
    # the same file still tracks at the class's depth
    assert main(["track", "--grid", str(old), "--measurements", str(measured), "--out", str(out)]) == 0


def test_grids_plot_k_against_target_depth(tiny_depth_grid_file, tmp_path, capsys):
    out = tmp_path / "depth.png"
    assert main(["grids", "plot", str(tiny_depth_grid_file), "--out", str(out), "--what", "depth",
                 "--class", "SUB", "--band", "FB1"]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert f"wrote {out} (K against target depth and range)" in capsys.readouterr().out


@pytest.mark.parametrize("args, message", [
    (["--bearing", "45"], "a bearing is for a bearing-dependent grid"),
    (["--class", "TANKER"], "class 'TANKER' is not a class of the grid (SUB, SHIP)"),
    (["--band", "FB9"], "band 'FB9' is not a band of the grid (FB1, F500)"),
    (["--bathymetry", "relief.nc"], "the figure of K against target depth has no map"),
])
def test_hostile_depth_plots(tiny_depth_grid_file, tmp_path, capsys, args, message):
    out = tmp_path / "depth.png"
    assert main(["grids", "plot", str(tiny_depth_grid_file), "--out", str(out), "--what", "depth", *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error:") and message in err[0], err
    assert list(tmp_path.iterdir()) == []


def test_a_depth_plot_of_a_grid_without_tl_obs_writes_nothing(tiny_grid_file, tmp_path, capsys):
    out = tmp_path / "depth.png"
    assert main(["grids", "plot", str(tiny_grid_file), "--out", str(out), "--what", "depth"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no TL from the observer depth" in err[0], err
    assert list(tmp_path.iterdir()) == []
