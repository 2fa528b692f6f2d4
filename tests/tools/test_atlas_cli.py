"""``tmakit atlas`` through the real command line: build, show, plot, sample and hostile inputs."""

from __future__ import annotations

import json
import subprocess
import sys

import pandas as pd
import pytest

from acoustics.grid.atlas.store import open_store
from tests.acoustics.atlas.atlasarea import write_atlas_area

pytestmark = pytest.mark.bellhop


def _tmakit(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "tools.cli", *map(str, args)], capture_output=True, text=True,
                          cwd=cwd)


@pytest.fixture(scope="module")
def store(tmp_path_factory):
    folder = tmp_path_factory.mktemp("atlas-cli")
    area = write_atlas_area(folder, months=(8,))
    out = folder / "a.zarr"
    done = _tmakit("atlas", "build", area, "--out", out, "--workers", "2", "--json")
    assert done.returncode == 0, done.stderr
    info = json.loads(done.stdout)
    assert info["tables"] == 6 and info["tables_built"] == 6
    again = _tmakit("atlas", "build", area, "--out", out, "--workers", "2")
    assert again.returncode == 0 and "(0 built, 6 up to date)" in again.stdout
    return area, out


def test_show_plot_and_sample(store, tmp_path):
    area, out = store
    shown = _tmakit("atlas", "show", out)
    assert shown.returncode == 0 and "tables complete: 6 of 6" in shown.stdout and "left out (3)" in shown.stdout
    png = tmp_path / "map.png"
    assert _tmakit("atlas", "plot", out, "--out", png, "--what", "k", "--range-km", "4").returncode == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    points = tmp_path / "p.csv"
    points.write_text("obs_lat_deg,obs_lon_deg,month,class,band,bearing_deg,range_m,depth_m\n"
                      "43.0,5.0,8,TV,FB2,90,5000,\n43.0,5.0,8,TV,FB2,90,5000,8\n")
    result = tmp_path / "s.csv"
    done = _tmakit("atlas", "sample", out, "--points", points, "--out", result)
    assert done.returncode == 0, done.stderr
    df = pd.read_csv(result)
    assert list(df.columns[-2:]) == ["k_db", "tl_db"] and len(df) == 2
    # a depth given as the class's own (8 m) gives K = S - TL there: the table's K within the
    # linear-in-depth TL between the 0 and 50 m rows of the atlas's axis (a few dB at most here)
    assert abs(df["k_db"][0] - df["k_db"][1]) < 6.0
    # midway between a slope position and the shelf-edge one north of it: the default weights
    # (tempered by the water) and the bilinear ones alone give different K, the same at a position
    atlas = open_store(out)
    mid = 0.5 * (atlas.lat_deg[1] + atlas.lat_deg[4])
    points.write_text("obs_lat_deg,obs_lon_deg,month,class,band,bearing_deg,range_m\n"
                      f"{mid},{atlas.lon_deg[1]},8,TV,FB2,90,5000\n{atlas.lat_deg[1]},{atlas.lon_deg[1]},8,TV,FB2,90,5000\n")
    k = {}
    for weights in ("water", "bilinear"):
        done = _tmakit("atlas", "sample", out, "--points", points, "--out", result, "--weights", weights)
        assert done.returncode == 0, done.stderr
        k[weights] = pd.read_csv(result)["k_db"].to_numpy()
    assert abs(k["water"][0] - k["bilinear"][0]) > 0.01 and k["water"][1] == k["bilinear"][1]


@pytest.mark.parametrize(("args", "message"), [
    (["atlas", "show", "{tmp}/nothing.zarr"], "no such atlas"),
    (["atlas", "show", "{tmp}"], "not a tmakit atlas"),
    (["atlas", "build", "{area}", "--out", "{tmp}/notes.txt"], "exists and is not a tmakit atlas (a file); --force"),
    (["atlas", "build", "{area}", "--out", "{tmp}/x.zarr", "--workers", "0"], "--workers: must be >= 1"),
    (["atlas", "build", "{area}", "--out", "{tmp}/x.zarr", "--scheduler", "http://evil"], "scheduler 'http://evil': expected tcp://HOST:PORT"),
    (["atlas", "build", "shelf-break", "--out", "{tmp}/x.zarr"], "has no [atlas]"),
    (["atlas", "plot", "{store}", "--out", "{tmp}/m.png", "--class", "XX"], "class 'XX' is not in the atlas"),
    (["atlas", "plot", "{store}", "--out", "{tmp}/m.png", "--month", "3"], "month 3 is not in the atlas"),
    (["atlas", "plot", "{store}", "--out", "{tmp}/m.png", "--what", "k", "--range-km", "99"], "outside the tables'"),
    (["atlas", "sample", "{store}", "--points", "{tmp}/bad.csv", "--out", "{tmp}/o.csv"], "missing column 'range_m'"),
    (["atlas", "sample", "{store}", "--points", "{tmp}/far.csv", "--out", "{tmp}/o.csv"],
     "row 2: 45.00000 N 5.00000 E is outside the atlas's lattice"),
    (["atlas", "sample", "{store}", "--points", "{tmp}/nan.csv", "--out", "{tmp}/o.csv"],
     "row 1, column range_m: 'nan' is not a number"),
    (["atlas", "sample", "{store}", "--points", "{tmp}/far.csv", "--out", "{tmp}/o.csv", "--weights", "cubic"],
     "--weights: invalid choice: 'cubic'"),
])
def test_hostile_inputs_end_with_one_error_line_and_nothing_written(store, tmp_path, args, message):
    area, out = store
    (tmp_path / "notes.txt").write_text("keep me")
    (tmp_path / "bad.csv").write_text("obs_lat_deg,obs_lon_deg,month,class,band,bearing_deg\n43,5,8,TV,FB2,0\n")
    (tmp_path / "far.csv").write_text("obs_lat_deg,obs_lon_deg,month,class,band,bearing_deg,range_m\n"
                                      "43.0,5.0,8,TV,FB2,0,100\n45.0,5.0,8,TV,FB2,0,100\n")
    (tmp_path / "nan.csv").write_text("obs_lat_deg,obs_lon_deg,month,class,band,bearing_deg,range_m\n"
                                      "43.0,5.0,8,TV,FB2,0,nan\n")
    before = sorted(p.name for p in tmp_path.iterdir())
    done = _tmakit(*[a.format(tmp=tmp_path, area=area, store=out) for a in args])
    lines = done.stderr.strip().splitlines()
    assert done.returncode == 2 and len(lines) == 1 and lines[0].startswith("error: "), done.stderr
    assert message in lines[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == before
    assert (tmp_path / "notes.txt").read_text() == "keep me"
