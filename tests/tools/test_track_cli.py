"""tmakit simulate / track / experiment through the CLI, including bad input."""

from pathlib import Path

import pandas as pd
import pytest

from tools.cli import main
from tracker.trackfile import TRACK_COLUMNS

BAD = Path(__file__).parent.parent / "data" / "malformed"


@pytest.mark.bellhop
def test_simulate_then_track(tiny_grid_file, tmp_path, capsys):
    import xarray as xr

    # the tiny grid's classes and bands: a scenario for its first class
    g = xr.open_dataset(tiny_grid_file)
    cls, cls_depth = str(g["class"].values[0]), float(g["source_depth_m"].values[0])
    g.close()
    sc = tmp_path / "sc.toml"
    sc.write_text((BAD / "scenario" / "unknown_key.toml").read_text()
                  .replace('colour = "red"', "").replace('"TV"', f'"{cls}"')
                  .replace("depth_m = 8.0", f"depth_m = {cls_depth}")
                  .replace("130.0", "150.0").replace("10000.0", "3000.0"))
    assert main(["simulate", str(sc), "--grid", str(tiny_grid_file), "--out",
                 str(tmp_path / "sim")]) == 0
    assert main(["track", "--grid", str(tiny_grid_file), "--measurements",
                 str(tmp_path / "sim" / "measurements.csv"), "--out",
                 str(tmp_path / "track.csv")]) == 0
    df = pd.read_csv(tmp_path / "track.csv")
    assert list(df.columns) == list(TRACK_COLUMNS) and set(df["method"]) == {"ml"}
    assert main(["track", "--grid", str(tiny_grid_file), "--measurements",
                 str(BAD / "measurements" / "unknown_band.csv"), "--out",
                 str(tmp_path / "bad.csv")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error:") and "level_db_FB9" in err[0]
    assert not (tmp_path / "bad.csv").exists()


def test_simulate_bad_scenario(tmp_path, capsys):
    assert main(["simulate", str(BAD / "scenario" / "course_out_of_range.toml"), "--grid",
                 "x.nc", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "course_deg" in err[0] and "Traceback" not in err[0]
    assert not (tmp_path / "o").exists()


def test_experiment_runs_must_be_a_cube(tmp_path, capsys):
    assert main(["experiment", "gm", "gm-tv-30km", "--runs", "10", "--grid", "x.nc",
                 "--out", str(tmp_path)]) == 2
    assert "--runs: must be a cube" in capsys.readouterr().err


@pytest.mark.bellhop
def test_track_observer_depth_outside_the_grid(tiny_grid_file, tmp_path, capsys):
    import xarray as xr

    g = xr.open_dataset(tiny_grid_file)
    depth = g["depth"].values
    band = str(g["band"].values[0])
    g.close()
    bad_depth = float(depth[-1]) + 500.0
    rows = ["t_s,obs_x_m,obs_y_m,obs_depth_m,bearing_deg,bearing_sigma_deg,"
            f"level_db_{band},snr_db_{band}"]
    for i in range(5):
        z = bad_depth if i == 3 else float(depth[0])
        rows.append(f"{10.0 * i},{25.0 * i},0,{z:g},45.0,0.5,80.0,10.0")
    csv = tmp_path / "deep.csv"
    csv.write_text("\n".join(rows) + "\n")
    out = tmp_path / "track.csv"
    assert main(["track", "--method", "ml", "--grid", str(tiny_grid_file), "--measurements",
                 str(csv), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error:"), err
    assert "row 4, column obs_depth_m" in err[0] and f"{bad_depth:g} m is outside" in err[0]
    assert not out.exists()
