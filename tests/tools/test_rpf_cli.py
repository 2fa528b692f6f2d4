"""``tracker.track`` with the particle filters, from a measurement CSV (what ``tmakit track --method
rpf|rpf-bot`` calls)."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from numpy.testing import assert_allclose

import acoustics
import envdata
from acoustics.errors import GridFileError
from tools.studies.idm import simulate
from tools.studies.idm_scenarios import get_scenario
from tracker import rpf
from tracker.errors import MeasurementFileError
from tracker.measurements import Measurements, read_measurements, write_measurements
from tracker.track import track
from tracker.trackfile import TRACK_COLUMNS, write_track

pytestmark = pytest.mark.bellhop


@pytest.fixture(scope="module")
def munk_path(tmp_path_factory):
    path = tmp_path_factory.mktemp("rpf") / "munk-1000.nc"
    acoustics.write_grid(acoustics.build_grid(envdata.load_area("munk-1000")), path)
    return path


@pytest.fixture(scope="module")
def munk(munk_path):
    return acoustics.open_tables(munk_path)


@pytest.fixture(scope="module")
def static_csv(munk, tmp_path_factory):
    """60 cycles of the static-observer scenario written as a measurement CSV."""
    sc = get_scenario("idm-static")
    tables = munk
    prof = tables.level_profile(tables.class_index("ship"), tables.band_index("F50"), 300.0)
    b, lv = simulate(sc, prof, 1, np.random.default_rng(4))
    n = 61
    m = Measurements(source="sim", t_s=sc.t_s[:n], obs_x_m=np.zeros(n), obs_y_m=np.zeros(n),
                     obs_depth_m=np.full(n, 300.0), bearing_deg=np.degrees(b[0, :n]) % 360,
                     bearing_sigma_deg=np.full(n, np.nan), band_names=("F50",),
                     level_db=lv[0, :n, None], snr_db=np.full((n, 1), np.nan))
    path = tmp_path_factory.mktemp("meas") / "measurements.csv"
    write_measurements(path, m)
    return path


def _read(path, munk):
    return read_measurements(path, grid_band_names=list(munk.band_names))


def test_track_rpf_gives_track_rows_and_is_repeatable(munk, static_csv, tmp_path):
    m = _read(static_csv, munk)
    df = track(munk, m, method="rpf", rng=np.random.default_rng(1),
               rpf_config=rpf.RpfConfig(n_particles=1000))
    assert tuple(df.columns) == TRACK_COLUMNS
    assert len(df) == len(m) and (df["method"] == "rpf").all() and (df["class"] == "ship").all()
    again = track(munk, m, method="rpf", rng=np.random.default_rng(1),
                  rpf_config=rpf.RpfConfig(n_particles=1000))
    assert_allclose(again["x_m"], df["x_m"], rtol=0, atol=0)
    sc = get_scenario("idm-static")
    truth = sc.target_state(m.t_s)
    err = np.hypot(df["x_m"] - truth[:, 0], df["y_m"] - truth[:, 1])
    assert err.iloc[-1] < 2000.0  # the SPL pins the range; BOT alone is ~4 km off here
    assert (df["range_sd_m"] > 0).all() and (df["course_sd_deg"] > 0).all()
    write_track(tmp_path / "track.csv", df)
    assert (tmp_path / "track.csv").exists()


def test_nan_levels_use_the_bearing_alone(munk, static_csv, tmp_path):
    m = _read(static_csv, munk)
    levels = m.level_db.copy()
    levels[5:20] = np.nan
    m2 = Measurements(source="gaps", t_s=m.t_s, obs_x_m=m.obs_x_m, obs_y_m=m.obs_y_m,
                      obs_depth_m=m.obs_depth_m, bearing_deg=m.bearing_deg,
                      bearing_sigma_deg=m.bearing_sigma_deg, band_names=m.band_names,
                      level_db=levels, snr_db=m.snr_db)
    df = track(munk, m2, method="rpf", rng=np.random.default_rng(2),
               rpf_config=rpf.RpfConfig(n_particles=500))
    assert np.isfinite(df[["x_m", "y_m", "range_sd_m"]].to_numpy()).all()
    bot = track(munk, m2, method="rpf-bot", rng=np.random.default_rng(2),
                rpf_config=rpf.RpfConfig(n_particles=500))
    assert (bot["method"] == "rpf-bot").all() and len(bot) == len(m2)


def test_missing_level_column_band_class_and_depth_are_errors(munk, static_csv, tmp_path):
    m = _read(static_csv, munk)
    no_levels = Measurements(source="nolevels.csv", t_s=m.t_s, obs_x_m=m.obs_x_m,
                             obs_y_m=m.obs_y_m, obs_depth_m=m.obs_depth_m,
                             bearing_deg=m.bearing_deg, bearing_sigma_deg=m.bearing_sigma_deg,
                             band_names=(), level_db=np.empty((len(m), 0)),
                             snr_db=np.empty((len(m), 0)))
    rng = np.random.default_rng(0)
    with pytest.raises(MeasurementFileError, match=r"nolevels.csv: method rpf needs a level "
                                                   r"column level_db_NAME"):
        track(munk, no_levels, method="rpf", rng=rng)
    with pytest.raises(GridFileError, match=r"band 'F100' is not in the grid \(bands: F50\)"):
        track(munk, m, method="rpf", rng=rng, band="F100")
    with pytest.raises(GridFileError, match=r"class 'sub' is not in the grid"):
        track(munk, m, method="rpf", rng=rng, cls_name="sub")
    deep = Measurements(source="deep.csv", t_s=m.t_s, obs_x_m=m.obs_x_m, obs_y_m=m.obs_y_m,
                        obs_depth_m=np.where(np.arange(len(m)) == 3, 1200.0, 300.0),
                        bearing_deg=m.bearing_deg, bearing_sigma_deg=m.bearing_sigma_deg,
                        band_names=m.band_names, level_db=m.level_db, snr_db=m.snr_db)
    with pytest.raises(MeasurementFileError, match=r"deep.csv: row 4, column obs_depth_m: 1200 m "
                                                   r"is outside the grid's depth axis \[0, 1000\]"):
        track(munk, deep, method="rpf", rng=rng)
    nob = Measurements(source="nob.csv", t_s=m.t_s, obs_x_m=m.obs_x_m, obs_y_m=m.obs_y_m,
                       obs_depth_m=m.obs_depth_m, bearing_deg=np.full(len(m), math.nan),
                       bearing_sigma_deg=m.bearing_sigma_deg, band_names=m.band_names,
                       level_db=m.level_db, snr_db=m.snr_db)
    with pytest.raises(MeasurementFileError, match=r"nob.csv: column bearing_deg: no bearing"):
        track(munk, nob, method="rpf-bot", rng=rng)
    with pytest.raises(MeasurementFileError, match=r"method 'ml' is not an RPF method"):
        rpf.track_measurements(munk, m, method="ml", rng=rng)


def test_cli_track_rpf_vp_writes_a_track(munk_path, static_csv, tmp_path, capsys):
    # the variance-preserving variant through the command line, on the real munk-1000 grid file
    from tools.cli import main

    out = tmp_path / "track.csv"
    assert main(["track", "--grid", str(munk_path), "--measurements", str(static_csv),
                 "--out", str(out), "--method", "rpf-vp", "--seed", "3"]) == 0
    df = pd.read_csv(out)
    assert tuple(df.columns) == TRACK_COLUMNS and (df["method"] == "rpf-vp").all()
    truth = get_scenario("idm-static").target_state(df["t_s"].to_numpy())
    err = np.hypot(df["x_m"] - truth[:, 0], df["y_m"] - truth[:, 1])
    assert err.iloc[-1] < 2000.0  # as for rpf: the SPL pins the range
    with pytest.raises(SystemExit) as exc:  # argparse rejects an unknown method
        main(["track", "--grid", str(munk_path), "--measurements", str(static_csv),
              "--out", str(tmp_path / "no.csv"), "--method", "rpf-vq"])
    assert exc.value.code == 2
    assert not (tmp_path / "no.csv").exists()


def test_cli_experiment_idm_with_the_filters_level_sigma(munk_path, tmp_path, capsys):
    import json

    from tools.cli import main

    out = tmp_path / "m"
    assert main(["experiment", "idm", "idm-maneuvering", "--runs", "4", "--grid", str(munk_path),
                 "--out", str(out), "--level-sigma-db", "4", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["level_sigma_db"] == 4.0
    # the bound with levels is below the bearings-only bound after the turn (30 min: 54 m
    # against 72 m), and both are in the CSV and the JSON
    at = data["at"]["30"]
    assert at["crlb_spl_m"] < at["crlb_bot_m"]
    frame = pd.read_csv(out / "idm-maneuvering_rmse.csv")
    assert {"crlb_bot_m", "crlb_spl_m"} <= set(frame.columns)
    assert (out / "idm-maneuvering_rmse.png").exists()


@pytest.mark.parametrize("argv, message", [
    (["experiment", "idm", "idm-static", "--level-sigma-db", "-1"],
     "error: level sigma_l: must be a positive number of dB, got -1"),
    (["experiment", "idm", "idm-static", "--level-sigma-db", "nan"],
     "error: level sigma_l: must be a positive number of dB, got nan"),
    (["experiment", "gm", "gm-tv-30km", "--level-sigma-db", "4", "--grid", "x.nc"],
     "error: --level-sigma-db: only the idm study has it (the gm tracker takes its level sd "
     "from the SNR, eq. 11)"),
])
def test_cli_experiment_bad_level_sigma_is_one_line_and_writes_nothing(argv, message, tmp_path,
                                                                        capsys):
    from tools.cli import main

    out = tmp_path / "o"
    assert main(argv + ["--out", str(out)]) == 2
    assert capsys.readouterr().err.strip() == message
    assert not out.exists()


def test_cli_range_prior_holds_the_first_cycles_inside_it(munk_path, static_csv, tmp_path):
    """--range-prior NEAR,FAR: the filter's particles start log-uniform between the two, so on
    bearings alone its first estimates stay between them; the default starts at 1 km and
    reaches the grid's last range, much wider."""
    from tools.cli import main
    from tracker.rpf.track import default_range_span_m

    narrow, wide = tmp_path / "narrow.csv", tmp_path / "wide.csv"
    for out, extra in ((narrow, ["--range-prior", "3,5"]), (wide, [])):
        assert main(["track", "--grid", str(munk_path), "--measurements", str(static_csv),
                     "--out", str(out), "--method", "rpf-bot", "--seed", "2", *extra]) == 0
    a, b = pd.read_csv(narrow), pd.read_csv(wide)
    assert ((a["range_m"].iloc[:3] > 3000.0) & (a["range_m"].iloc[:3] < 5000.0)).all()
    # log-uniform over 3-5 km: sd about 0.57 km; over 1 km to the grid's end several km
    assert a["range_sd_m"].iloc[0] < 700.0
    near, far = default_range_span_m(acoustics.open_tables(munk_path))
    assert near == 1000.0 and b["range_sd_m"].iloc[0] > 3.0 * a["range_sd_m"].iloc[0], (far, b["range_sd_m"].iloc[0])


@pytest.mark.parametrize("argv, message", [
    (["--range-prior", "5"], "give two ranges in km, NEAR,FAR"),
    (["--range-prior", "8,3"], "range prior 8-3 km: give two ranges, the near one first"),
    (["--range-prior", "2,5000"], "range prior 2-5000 km: the tables reach"),
    (["--range-prior", "2,8", "--method", "ml"], "a range prior is for the particle filters"),
])
def test_cli_bad_range_prior_is_one_line_and_writes_nothing(argv, message, munk_path, static_csv, tmp_path, capsys):
    from tools.cli import main

    out = tmp_path / "track.csv"
    base = ["track", "--grid", str(munk_path), "--measurements", str(static_csv), "--out", str(out)]
    if "--method" not in argv:
        base += ["--method", "rpf"]
    try:
        code = main(base + argv)
    except SystemExit as exc:  # argparse's own: usage and the reason on stderr, exit 2
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2 and message in err, err
    assert "Traceback" not in err and not out.exists()
