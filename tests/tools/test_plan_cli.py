"""Detection planning through the real command line: ``grids plot --what pd``, the build's range
check, ``atlas plot --what pd``, ``plan track`` and ``plan months``, and their bad inputs (one
``error:`` line, exit 2, nothing written)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import xarray as xr
from numpy.testing import assert_allclose

from acoustics.grid.atlas.store import open_store
from acoustics.grid.pdmap import pd_map
from envdata.receiver import load_receiver
from tests.acoustics.atlas.atlasarea import write_atlas_area
from tests.acoustics.plots.test_radialplots import png_size
from tests.tools.test_plot_bearing_cli import run_error, run_json
from tools import cli

pytestmark = pytest.mark.bellhop


@pytest.fixture(scope="module")
def atlas(tmp_path_factory) -> Path:
    """Two listed positions, February and August, four radials to 10 km: the test atlas's sea with a
    quieter transport and a smaller array, so that its detection ends inside the tables."""
    folder = tmp_path_factory.mktemp("plan-atlas")
    area = write_atlas_area(folder)
    text = area.read_text()
    for old, new in (("lat_deg = [42.975, 43.15]\nlon_deg = [4.90, 5.10]\nspacing_km = 8.0\n",
                      "positions = [[43.0, 5.0], [42.95, 5.05]]\n"),
                     ("directivity_index_db = 42.0", "directivity_index_db = 12.0"),
                     ("noise_mean_db = 133.02", "noise_mean_db = 101.0")):
        assert old in text
        text = text.replace(old, new)
    area.write_text(text)
    out = folder / "a.zarr"
    assert cli.main(["atlas", "build", str(area), "--out", str(out), "--workers", "2"]) == 0
    return out


def test_grids_plot_pd_writes_the_map_its_netcdf_and_the_ranges(capsys, tmp_path, tiny_radial_grid_file):
    data = run_json(capsys, "grids", "plot", tiny_radial_grid_file, "--what", "pd", "--out", tmp_path / "pd.png")
    assert data["files"] == {"map": str(tmp_path / "pd.png"), "netcdf": str(tmp_path / "pd.nc"),
                             "bottom": str(tmp_path / "pd-bottom.png")}
    assert data["what"] == "pd" and data["band"] == "any"
    assert png_size(tmp_path / "pd.png")[0] > 1000
    with xr.open_dataset(tmp_path / "pd.nc") as ds:
        assert ds.attrs["Conventions"] == "CF-1.8" and ds["pd"].attrs["grid_mapping"] == "crs"
    sub, ship = data["pd"]["SUB"], data["pd"]["SHIP"]
    assert sub["bearing_deg"] == [0.0, 120.0, 240.0]
    # the submarine's ranges end inside the 5 km table; the ship's pass it: no range, said so
    for level in ("0.9", "0.5", "0.1"):
        assert all(0 < r < 5000 for r in sub["rows"]["any"]["range_m"][level])
        assert ship["rows"]["FB1"]["range_m"][level] == [None] * 3
        assert ship["rows"]["FB1"]["beyond_table"][level] == [True] * 3
    out = capsys.readouterr().out
    assert cli.main(["grids", "plot", str(tiny_radial_grid_file), "--what", "pd", "--band", "FB1",
                     "--out", str(tmp_path / "pd.png")]) == 0
    out = capsys.readouterr().out
    assert "SHIP FB1: P_D 0.9 / 0.5 / 0.1 out to - / - / -; P_D >= 0.1 still at the table's last range (5 km) " \
           "on 3 of 3 bearing(s): beyond the table" in out


def test_grids_plot_pd_on_a_flat_grid_is_one_png(capsys, tmp_path, tiny_grid_file):
    data = run_json(capsys, "grids", "plot", tiny_grid_file, "--what", "pd", "--out", tmp_path / "f.png",
                    "--sigma-db", "4")
    assert data["files"] == {"pd": str(tmp_path / "f.png")}
    assert [p.name for p in tmp_path.iterdir()] == ["f.png"]
    assert data["pd"]["SUB"]["bearing_deg"] is None and data["pd"]["SUB"]["sigma_db"] == {"min": 4.0, "max": 4.0}
    assert data["pd"]["SHIP"]["rows"]["any"]["beyond_table"]["0.1"] is True


def test_the_build_says_where_detection_passes_the_table_s_end(capsys, tmp_path, tiny_area_path):
    data = run_json(capsys, "grids", "build", tiny_area_path, "--out", tmp_path / "g.nc", "--workers", "2")
    reach = {(r["class"], r["band"]): r for r in data["reach"]}
    assert reach[("SUB", "FB1")]["inside"] and reach[("SUB", "FB1")]["range_needed_m"] is None
    ship = reach[("SHIP", "F500")]
    assert not ship["inside"] and ship["pd_at_table_end"] > 0.1 and ship["range_needed_m"] > 5000.0
    assert cli.main(["grids", "build", str(tiny_area_path), "--out", str(tmp_path / "g.nc")]) == 0
    out = capsys.readouterr().out
    assert "SHIP F500: P_D 1.00 at the table's last range (5 km) on 1 of 1 bearing(s), above 0.1; the range " \
           "axis would have to reach about" in out


@pytest.mark.parametrize("options, message", [
    (["--sigma-db", "0"], "--sigma-db: must be > 0 dB"),
    (["--sigma-db", "-2"], "--sigma-db: must be > 0 dB"),
    (["--sigma-db", "nan"], "--sigma-db: must be > 0 dB"),
    (["--class", "XX"], "class 'XX' is not a class of the grid (SUB, SHIP)"),
    (["--band", "FB9"], "band 'FB9' is not a band of the grid (FB1, F500, or any)"),
])
def test_bad_pd_options_are_one_line_and_write_nothing(capsys, tmp_path, tiny_radial_grid_file, options, message):
    line = run_error(capsys, "grids", "plot", tiny_radial_grid_file, "--what", "pd", "--out", tmp_path / "m.png",
                     *options)
    assert message in line
    assert list(tmp_path.iterdir()) == []


def test_other_bad_plot_requests(capsys, tmp_path, tiny_radial_grid_file, tiny_grid_file):
    assert "--sigma-db is for the probability of detection" in run_error(
        capsys, "grids", "plot", tiny_radial_grid_file, "--what", "k", "--out", tmp_path / "m.png", "--sigma-db", "3")
    assert "needs a name of its own" in run_error(
        capsys, "grids", "plot", tiny_radial_grid_file, "--what", "pd", "--out", tmp_path / "m.nc")
    assert "a section's bearing is for a bearing-dependent grid" in run_error(
        capsys, "grids", "plot", tiny_grid_file, "--what", "pd", "--out", tmp_path / "m.png", "--bearing", "10")
    notes = tmp_path / "m.nc"
    notes.write_text("my notes\n")
    assert "m.nc: exists and is not a tmakit netCDF file" in run_error(
        capsys, "grids", "plot", tiny_radial_grid_file, "--what", "pd", "--out", tmp_path / "m.png")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.nc"] and notes.read_text() == "my notes\n"


def test_atlas_plot_pd_and_the_months_side_by_side(capsys, tmp_path, atlas):
    data = run_json(capsys, "atlas", "plot", atlas, "--what", "pd", "--month", "2", "--out", tmp_path / "a.png")
    assert data["files"] == {"map": str(tmp_path / "a.png"), "netcdf": str(tmp_path / "a.nc")}
    with xr.open_dataset(tmp_path / "a.nc") as ds:
        assert ds["pd"].dims == ("origin", "lat", "lon") and list(ds["origin"].values) == [0, 1]
        assert ds.attrs["month"] == 2 and ds["origin_lat_deg"].attrs["units"] == "degrees_north"
    assert [p["origin"] for p in data["positions"]] == [0, 1]
    store = open_store(atlas)
    data = run_json(capsys, "plan", "months", atlas, "--out", tmp_path / "m.csv", "--plot", tmp_path / "m.png")
    table = pd.read_csv(tmp_path / "m.csv")
    assert len(table) == 2 * 2 * 3 and set(table["month"]) == {2, 8} and png_size(tmp_path / "m.png")[0] > 800
    # each row is the median over the radials of the position's P_D map, written out
    for month in (2, 8):
        for o in (0, 1):
            pm = pd_map(store.sel(month=month, origin=o), "TV", store.bearing_deg)
            row = table[(table["month"] == month) & (table["origin"] == o) & (table["level"] == 0.5)].iloc[0]
            ranges = pm.ranges_m[0.5][-1]
            assert not pm.beyond[0.5][-1].any() and np.isfinite(ranges).all()
            assert_allclose(row["median_m"], np.median(ranges))
            assert row["bearings_beyond"] == 0 and not row["median_beyond_table"]
    # the two months differ somewhere: what the side by side is for
    a = table[(table["month"] == 2) & (table["level"] == 0.5)]["median_m"].to_numpy()
    b = table[(table["month"] == 8) & (table["level"] == 0.5)]["median_m"].to_numpy()
    assert np.max(np.abs(a - b)) >= 200.0


@pytest.mark.parametrize("argv, message", [
    (["atlas", "plot", "{atlas}", "--what", "pd", "--out", "{tmp}/x.png", "--month", "3"], "month 3 is not in the atlas"),
    (["atlas", "plot", "{atlas}", "--what", "pd", "--out", "{tmp}/x.png", "--band", "FB9"],
     "band 'FB9' is not in the atlas (FB2, or any)"),
    (["atlas", "plot", "{atlas}", "--what", "pd", "--out", "{tmp}/x.png", "--class", "XX"], "class 'XX' is not in"),
    (["atlas", "plot", "{atlas}", "--what", "pd", "--out", "{tmp}/x.png", "--sigma-db", "-1"], "--sigma-db: must be > 0"),
    (["plan", "months", "{atlas}", "--out", "{tmp}/x.csv", "--months", "2", "5"], "month 5 is not in the atlas"),
    (["plan", "months", "{atlas}", "--out", "{tmp}/x.csv", "--class", "NPS"], "class 'NPS' is not in the atlas"),
    (["plan", "months", "{atlas}", "--out", "{tmp}/x.csv", "--sigma-db", "0"], "--sigma-db: must be > 0"),
])
def test_bad_atlas_requests(capsys, tmp_path, atlas, argv, message):
    line = run_error(capsys, *[a.format(atlas=atlas, tmp=tmp_path) for a in argv])
    assert message in line
    assert list(tmp_path.iterdir()) == []


SCENARIO = """[scenario]
name = "tiny-approach"
area = "tiny-munk"
cycle_s = 10.0
target_class = "SUB"
[observer]
x_m = 0.0
y_m = 0.0
depth_m = 100.0
[[observer.tacks]]
course_deg = 90.0
speed_mps = 1.0
duration_s = 600.0
[target]
depth_m = 150.0
x_m = 0.0
y_m = 4800.0
[[target.tacks]]
course_deg = 180.0
speed_mps = 7.0
noise_db = 88.0
duration_s = 600.0
"""


def test_plan_track_from_a_scenario_and_from_its_truth(capsys, tmp_path, tiny_grid_file):
    scenario = tmp_path / "s.toml"
    scenario.write_text(SCENARIO)
    data = run_json(capsys, "plan", "track", "--grid", tiny_grid_file, "--scenario", scenario, "--out",
                    tmp_path / "p.csv", "--plot", tmp_path / "p.png", "--look-sd-db", "1")
    table = pd.read_csv(tmp_path / "p.csv")
    assert list(table.columns) == ["t_s", "obs_x_m", "obs_y_m", "x_m", "y_m", "range_m", "bearing_deg", "pd_FB1",
                                   "pd_F500", "pd_any", "cum_pd_FB1", "cum_pd_F500", "cum_pd_any",
                                   "cum_pd_any_shared"]
    assert len(table) == data["looks"] == 61 and data["class"] == "SUB" and png_size(tmp_path / "p.png")[0] > 800
    assert np.all(np.diff(table["cum_pd_any"]) >= 0.0) and table["cum_pd_any"].iloc[-1] > 0.9
    first = data["first_detection"]["any"]
    assert 0.0 < first["mean_s_given_detected"] < 600.0 and first["median_s"] is not None
    assert any("independent" in a for a in data["assumptions"])
    # the same geometry from a CSV: range and bearing from the observer, the observer's positions
    table[["t_s", "obs_x_m", "obs_y_m", "range_m", "bearing_deg"]].assign(**{"class": "SUB"}).to_csv(
        tmp_path / "route.csv", index=False)
    again = run_json(capsys, "plan", "track", "--grid", tiny_grid_file, "--track", tmp_path / "route.csv",
                     "--out", tmp_path / "q.csv", "--look-sd-db", "1")
    assert again["observer_given"] and again["class"] == "SUB"
    assert_allclose(pd.read_csv(tmp_path / "q.csv")["cum_pd_any"], table["cum_pd_any"], rtol=0, atol=1e-5)


@pytest.mark.parametrize("text, options, message", [
    ("x_m,y_m\n0,1\n", [], "missing column 't_s'"),
    ("t_s,x_m,y_m\n0,1,zz\n", ["--class", "SUB"], "column 'y_m', row 1: 'zz' is not a finite number"),
    ("t_s,x_m,y_m\n10,1,2\n0,1,2\n", ["--class", "SUB"], "t_s must increase"),
    ("t_s,x_m,y_m,obs_y_m\n0,1,2,3\n", ["--class", "SUB"], "obs_y_m without its pair"),
    ("t_s,class,x_m,y_m\n0,SUB,1,2\n0,SHIP,1,2\n", [], "rows of several classes"),
    ("t_s,x_m,y_m\n0,1000,2\n", [], "the track names no class; say which with --class (SUB, SHIP)"),
    ("t_s,x_m,y_m\n0,1000,2\n", ["--class", "NPS"], "class 'NPS' is not a class of the grid"),
    ("t_s,x_m,y_m\n0,1000,2\n", ["--class", "SUB", "--sigma-db", "0"], "--sigma-db: must be > 0 dB"),
    ("t_s,x_m,y_m\n0,1000,2\n", ["--class", "SUB", "--look-sd-db", "-1"], "--look-sd-db: must be >= 0 dB"),
])
def test_bad_tracks_are_one_line_and_write_nothing(capsys, tmp_path, tiny_grid_file, text, options, message):
    track = tmp_path / "t.csv"
    track.write_text(text)
    old = tmp_path / "out.csv"
    old.write_text("a,b\n1,2\n")
    line = run_error(capsys, "plan", "track", "--grid", tiny_grid_file, "--track", track, "--out", old,
                     "--plot", tmp_path / "p.png", *options)
    assert message in line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv", "t.csv"] and old.read_text() == "a,b\n1,2\n"


def test_the_coverage_map_rings_a_median_at_the_table_s_edge(atlas):
    import dataclasses

    from acoustics.plots.atlasmap import coverage_figure

    store = open_store(atlas)
    fig, values = coverage_figure(store, what="detection", month=8)
    assert np.all(values < 10.0) and not [a for a in fig.axes[0].get_children() if a.get_gid() == "table-edge"]
    # a 30 dB larger array hears the transport past the 10 km tables: ringed, the edge is not a range
    store.area = dataclasses.replace(store.area, sonar=dataclasses.replace(store.area.sonar,
                                                                           directivity_index_db=42.0))
    fig, values = coverage_figure(store, what="detection", month=8)
    ring = [a for a in fig.axes[0].get_children() if a.get_gid() == "table-edge"]
    assert np.all(values == 10.0) and len(ring) == 1 and len(ring[0].get_offsets()) == 2


def test_the_demo_checks_its_p_d_netcdf_before_any_work(capsys, tmp_path):
    out = tmp_path / "demo"
    out.mkdir()
    (out / "shelf-break-pd.nc").write_text("my notes\n")
    line = run_error(capsys, "demo", "--out", out)
    assert line == (f"error: {out / 'shelf-break-pd.nc'}: exists and is not a tmakit netCDF file; not replaced "
                    f"(--force replaces it)")
    assert [p.name for p in out.iterdir()] == ["shelf-break-pd.nc"]


def _sonar_file(folder: Path, name: str, *, di_db: float, noise_db: float | None, slope: float = -5.0) -> Path:
    path = folder / f"{name}.toml"
    noise = "" if noise_db is None else (f"[noise]\nspectrum_level_1khz_db = {noise_db!r}\n"
                                         f"slope_db_per_octave = {slope!r}\n")
    path.write_text(f'name = "{name}"\ndescription = "test receiver"\n\n[sonar]\nbeamwidth_deg = 10.0\n'
                    f"directivity_index_db = {di_db!r}\nintegration_time_s = 10.0\ndetection_threshold = 5.0\n\n"
                    + noise)
    return path


def test_another_sonar_in_the_same_tables_moves_only_the_detection_rule(capsys, tmp_path, tiny_radial_tables,
                                                                        tiny_radial_grid_file):
    """Only N - DI enters the rule (acoustics/detection.py): a sonar with 6 dB less DI in a sea 6 dB
    quieter draws the area's own P_D map; a deaf one (DI 0 in a loud sea) brings the ship's ranges,
    which pass the 5 km table with the area's sonar, inside it."""
    area = tiny_radial_tables.area
    same = _sonar_file(tmp_path, "same", di_db=area.sonar.directivity_index_db - 6.0,
                       noise_db=area.noise.spectrum_level_1khz_db - 6.0, slope=area.noise.slope_db_per_octave)
    # 55 dB less sensitive: measured, the ship's 0.5 ranges fall inside the table from 45 dB (the
    # area's sonar + 25 dB of noise) to 65 dB (+45 dB) less; 55 is the middle of that span
    deaf = _sonar_file(tmp_path, "deaf", di_db=0.0, noise_db=area.noise.spectrum_level_1khz_db + 35.0)
    own = run_json(capsys, "grids", "plot", tiny_radial_grid_file, "--what", "pd", "--out", tmp_path / "own.png")
    moved = run_json(capsys, "grids", "plot", tiny_radial_grid_file, "--what", "pd", "--sonar", same,
                     "--out", tmp_path / "same.png")
    assert moved["sonar"] == "same" and "sonar" not in own
    for cls_name in ("SUB", "SHIP"):
        assert moved["pd"][cls_name]["rows"] == own["pd"][cls_name]["rows"]
    heard = run_json(capsys, "grids", "plot", tiny_radial_grid_file, "--what", "pd", "--sonar", deaf,
                     "--out", tmp_path / "deaf.png")
    ship = heard["pd"]["SHIP"]["rows"]["any"]
    assert ship["beyond_table"]["0.1"] == [False] * 3
    assert all(0 < r < 5000 for r in ship["range_m"]["0.5"])
    # the deaf sonar's P_D is below the area's wherever the area's is between 0 and 1
    base = pd_map(tiny_radial_tables, "SHIP", [0.0]).pd
    deafer = pd_map(tiny_radial_tables.with_receiver(load_receiver(deaf)), "SHIP", [0.0]).pd
    between = (base > 1e-6) & (base < 1 - 1e-6)
    assert between.any() and np.all(deafer[between] < base[between])


def test_the_built_in_planning_sonar_and_bad_sonar_files(capsys, tmp_path, tiny_radial_grid_file):
    from envdata.receiver import builtin_sonar_names
    assert "omni-buoy" in builtin_sonar_names()
    buoy = load_receiver("omni-buoy")
    assert buoy.sonar.directivity_index_db == 0.0 and buoy.noise is not None
    data = run_json(capsys, "grids", "plot", tiny_radial_grid_file, "--what", "detection", "--sonar", "omni-buoy",
                    "--out", tmp_path / "det.png")
    assert data["sonar"] == "omni-buoy" and (tmp_path / "det.png").is_file()
    no_sonar = tmp_path / "no-sonar.toml"
    no_sonar.write_text('name = "x"\n[noise]\nspectrum_level_1khz_db = 60.0\n')
    extra = _sonar_file(tmp_path, "extra", di_db=3.0, noise_db=None)
    extra.write_text(extra.read_text() + "depth_m = 5.0\n")
    negative = _sonar_file(tmp_path, "neg", di_db=-3.0, noise_db=None)
    bad_name = _sonar_file(tmp_path, "ok", di_db=3.0, noise_db=None)
    bad_name.write_text(bad_name.read_text().replace('name = "ok"', 'name = "a b"'))
    out = tmp_path / "x.png"
    for sonar, said in (("nope", "no built-in sonar of that name"), (no_sonar, "missing required table [sonar]"),
                        (extra, "unknown key 'depth_m'"), (negative, "directivity_index_db"),
                        (bad_name, "name"), (tmp_path, "is a directory")):
        line = run_error(capsys, "grids", "plot", tiny_radial_grid_file, "--what", "pd", "--sonar", sonar,
                         "--out", out)
        assert said in line, line
    line = run_error(capsys, "grids", "plot", tiny_radial_grid_file, "--what", "k", "--sonar", "omni-buoy",
                     "--out", out)
    assert "--sonar" in line
    assert not out.exists() and not (tmp_path / "x.nc").exists()
