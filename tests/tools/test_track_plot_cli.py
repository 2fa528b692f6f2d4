"""tmakit track --plot PNG [--truth CSV]: the picture of a track, through the command line.

The picture's data are read back from its artists (by gid) and compared with the files they
come from: the observer's path with the measurements, each track with the track CSV, and the
error curve with the distance between the track and the truth.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.acoustics.plots.test_radialplots import png_size
from tools.cli import main

BAD = Path(__file__).parent.parent / "data" / "malformed"
pytestmark = pytest.mark.bellhop


@pytest.fixture(scope="module")
def simulated(tiny_grid_file, tmp_path_factory):
    import xarray as xr

    folder = tmp_path_factory.mktemp("trackplot")
    with xr.open_dataset(tiny_grid_file) as g:
        cls, cls_depth = str(g["class"].values[0]), float(g["source_depth_m"].values[0])
    sc = folder / "sc.toml"
    sc.write_text((BAD / "scenario" / "unknown_key.toml").read_text()
                  .replace('colour = "red"', "").replace('"TV"', f'"{cls}"')
                  .replace("depth_m = 8.0", f"depth_m = {cls_depth}")
                  .replace("130.0", "150.0").replace("10000.0", "3000.0"))
    assert main(["simulate", str(sc), "--grid", str(tiny_grid_file), "--out", str(folder / "sim"),
                 "--seed", "2"]) == 0
    return folder / "sim"


def test_the_picture_shows_the_files_it_was_given(tiny_grid_file, simulated, tmp_path, capsys):
    from acoustics import open_tables
    from tracker.measurements import read_measurements
    from tracker.trackfile import read_track
    from tracker.trackplot import track_figure
    from tracker.truthfile import read_truth

    out, png = tmp_path / "t.csv", tmp_path / "t.png"
    assert main(["track", "--grid", str(tiny_grid_file), "--measurements", str(simulated / "measurements.csv"),
                 "--out", str(out), "--plot", str(png), "--truth", str(simulated / "truth.csv")]) == 0
    assert png_size(png)[0] > 800 and sorted(p.name for p in tmp_path.iterdir()) == ["t.csv", "t.png"]
    # the same figure from the files, read back by its artists (a flat grid: the local plane in km)
    tables = open_tables(tiny_grid_file)
    m = read_measurements(simulated / "measurements.csv", list(tables.band_names))
    track, truth = read_track(out), read_truth(simulated / "truth.csv")
    fig = track_figure(track, m, tables, truth=truth)
    artists = {a.get_gid(): a for ax in fig.axes for a in ax.get_lines() if a.get_gid()}
    x, y = artists["observer"].get_data()
    np.testing.assert_allclose(x, m.obs_x_m / 1000.0)
    np.testing.assert_allclose(y, m.obs_y_m / 1000.0)
    for cls, rows in track.groupby("class"):
        tx, _ = artists[f"track:{cls}"].get_data()
        np.testing.assert_allclose(tx, rows.x_m / 1000.0)
        t_min, err = artists[f"error:{cls}"].get_data()
        tx_true, ty_true = truth.at(rows.t_s.to_numpy())
        np.testing.assert_allclose(err, np.hypot(rows.x_m - tx_true, rows.y_m - ty_true))
        np.testing.assert_allclose(t_min, rows.t_s / 60.0)


@pytest.mark.parametrize("truth_text, message", [
    ("t_s,x_m\n0,1\n", "the header needs a y_m column"),
    ("t_s,x_m,y_m\n0,1,2\n0,1,2\n", "row 2, column t_s: 0 s is not after the previous row's 0 s"),
    ("t_s,x_m,y_m\n0,abc,2\n", "row 1, column x_m: 'abc' is not a number"),
    ("t_s,x_m,y_m\n0,1e30,2\n", "row 1, column x_m: 1e+30 m is beyond 20000 km"),
])
def test_a_bad_truth_is_one_error_line_and_nothing_is_written(tiny_grid_file, simulated, tmp_path, capsys,
                                                              truth_text, message):
    truth = tmp_path / "truth.csv"
    truth.write_text(truth_text)
    out, png = tmp_path / "out" / "t.csv", tmp_path / "out" / "t.png"
    out.parent.mkdir()
    assert main(["track", "--grid", str(tiny_grid_file), "--measurements", str(simulated / "measurements.csv"),
                 "--out", str(out), "--plot", str(png), "--truth", str(truth)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"error: {truth}") and message in err[0]
    assert list(out.parent.iterdir()) == []


def test_a_truth_without_a_picture_is_refused(tiny_grid_file, simulated, tmp_path, capsys):
    assert main(["track", "--grid", str(tiny_grid_file), "--measurements", str(simulated / "measurements.csv"),
                 "--out", str(tmp_path / "t.csv"), "--truth", str(simulated / "truth.csv")]) == 2
    assert "give --plot PNG too" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_the_plot_path_is_checked_before_tracking(tiny_grid_file, simulated, tmp_path, capsys):
    notes = tmp_path / "notes.png"
    notes.write_text("not a picture")
    assert main(["track", "--grid", str(tiny_grid_file), "--measurements", str(simulated / "measurements.csv"),
                 "--out", str(tmp_path / "t.csv"), "--plot", str(notes)]) == 2
    assert "not replaced" in capsys.readouterr().err and notes.read_text() == "not a picture"
    assert not (tmp_path / "t.csv").exists()
