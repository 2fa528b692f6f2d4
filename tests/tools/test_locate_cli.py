"""``tmakit locate`` and ``tmakit locate plan`` through the real command line (in process).

The paper's unit-free example (x0 = y0 = 10, VT = 3) is used at 1000 m per unit: target at
(10000, 10000) m, 5 m/s for 600 s per leg.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tools.cli import main

DATA = Path(__file__).resolve().parents[1] / "data"
MALFORMED = DATA / "malformed" / "locate"
PAPER_PAIR = DATA / "locate" / "paper_pair.csv"
PLAN_PAPER = ["locate", "plan", "--target-x-m", "10000", "--target-y-m", "10000",
              "--speed-mps", "5", "--leg-s", "600"]


def run_json(capsys, argv):
    rc = main([*argv, "--json"])
    out, err = capsys.readouterr()
    assert rc == 0, err
    return json.loads(out)


def test_locate_json_gives_the_fix_u_and_the_papers_region(capsys):
    data = run_json(capsys, ["locate", "--bearings", str(PAPER_PAIR)])
    assert_allclose([data["x_m"], data["y_m"]], [10000.0, 10000.0], atol=1e-3)
    # u of bearings 45 and 32.75 deg: cot(12.247 deg / 2)
    assert_allclose(data["u"], 1.0 / np.tan(np.radians(12.247324 / 2.0)), rtol=1e-6)
    assert_allclose(data["determinant"], 3.0 / np.sqrt(200.0), rtol=1e-6)  # eq. 10
    reg = data["region"]
    assert reg["kind"] == "quadrilateral"
    # the paper's numbers times 1000 m (tolerances: see tests/tracker/locate/test_regions.py)
    assert_allclose(reg["d13_eq25_m"], 493.6, atol=0.1)
    assert_allclose(reg["d24_m"], 4699.2, atol=1.0)
    assert_allclose(reg["area_diagonals_m2"], 1.16e6, atol=1e3)
    assert len(reg["vertices_m"]) == 4
    assert data["monte_carlo"] is None and data["plot"] is None


@pytest.mark.parametrize("method", ["crossing", "lsq", "mean"])
def test_locate_text_summary(capsys, method):
    rc = main(["locate", "--bearings", str(PAPER_PAIR), "--method", method])
    out, err = capsys.readouterr()
    assert rc == 0 and err == ""
    assert f"method {method}" in out
    assert "estimate: x = 10000.0 m, y = 10000.0 m" in out
    assert "conditioning number u = 9.321 (eq. 11)" in out
    assert "d13 = 493.6 m (eq. 25: 493.6 m)" in out
    assert "eq. 27: 4654.0 m" in out


def test_locate_many_bearings_with_extra_columns(capsys):
    csv = DATA / "locate" / "six_bearings_extra_columns.csv"
    data = run_json(capsys, ["locate", "--bearings", str(csv), "--method", "mean"])
    assert data["n_bearings"] == 6 and data["pairs_used"] == 5
    assert_allclose([data["x_m"], data["y_m"]], [-4000.0, 7500.0], atol=1e-3)
    assert data["region"]["kind"] == "polygon"
    assert data["region"]["area_m2"] > 0.0


def test_locate_plot_and_monte_carlo_are_repeatable(capsys, tmp_path):
    png = tmp_path / "fix.png"
    argv = ["locate", "--bearings", str(PAPER_PAIR), "--plot", str(png), "--trials", "300",
            "--seed", "3"]
    first = run_json(capsys, argv)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    second = run_json(capsys, argv[:3] + argv[5:])  # the same without the plot
    assert first["monte_carlo"] == second["monte_carlo"]
    mc = first["monte_carlo"]
    assert mc["trials"] == 300 and mc["fixes"] == 300
    assert mc["inside_fraction"] == 1.0  # crossing fixes of bearings within +-D_alpha
    assert abs(mc["mean_x_m"] - 10000.0) < 200.0 and abs(mc["mean_y_m"] - 10000.0) < 200.0
    assert [p.name for p in tmp_path.iterdir()] == ["fix.png"]  # no temporary left behind


def test_plan_reproduces_the_papers_first_pair_and_round_trips(capsys, tmp_path):
    out_csv, png = tmp_path / "route.csv", tmp_path / "plan.png"
    data = run_json(capsys, [*PLAN_PAPER, "--legs", "29", "--out", str(out_csv),
                             "--plot", str(png), "--trials", "200", "--seed", "1"])
    assert data["rule"] == "eq23" and data["legs"] == 29 and len(data["route"]) == 30
    reg = data["region"]
    assert_allclose(reg["d13_eq25_m"], 493.6, atol=0.1)       # paper 0.4936 x 1000 m
    assert_allclose(reg["d24_m"], 4699.2, atol=1.0)           # paper 4.6992 x 1000 m
    assert_allclose(reg["d24_eq27_m"], 4654.0, atol=0.1)      # eq. 27 as printed (paper 4666.2)
    assert_allclose(reg["area_m2"], 1.153e6, rtol=1e-3)
    assert data["u_last"] < data["u_first"]
    assert png.read_bytes()[:4] == b"\x89PNG"
    header = out_csv.read_text().splitlines()[0].split(",")
    assert header[:4] == ["t_s", "obs_x_m", "obs_y_m", "bearing_deg"]
    assert {"course_deg", "speed_mps", "u", "determinant", "d13_m", "d24_m"} <= set(header)
    # the route's own bearings locate the target
    fix = run_json(capsys, ["locate", "--bearings", str(out_csv)])
    assert_allclose([fix["x_m"], fix["y_m"]], [10000.0, 10000.0], atol=1e-3)
    assert fix["n_bearings"] == 30


def test_plan_eq17_gives_the_larger_d13(capsys):
    data = run_json(capsys, [*PLAN_PAPER, "--rule", "eq17", "--legs", "3"])
    assert_allclose(data["region"]["d13_m"], 504.5, atol=0.5)  # "near 0.505" x 1000 m
    u = [row["u"] for row in data["route"][1:]]
    assert u == sorted(u)  # eq. 17 moves away: conditioning degrades


def test_plan_text_summary(capsys):
    rc = main([*PLAN_PAPER, "--legs", "2", "--first-leg", "eq17"])
    out, err = capsys.readouterr()
    assert rc == 0 and err == ""
    assert "route, rule eq23 (first leg eq17)" in out
    lines = out.splitlines()
    assert lines[2].split()[:5] == ["1", "0", "0.0", "0.0", "45.00"]
    assert lines[3].split()[7] == lines[4].split()[7]  # Fig. 2: equal u for pairs 1-2 and 2-3


def test_plan_simulate_is_repeatable(capsys):
    argv = [*PLAN_PAPER, "--legs", "5", "--simulate", "--seed", "11"]
    a = run_json(capsys, argv)
    b = run_json(capsys, argv)
    assert a["route"] == b["route"] and a["simulated"]
    exact = run_json(capsys, [*PLAN_PAPER, "--legs", "5"])
    assert a["route"][1]["bearing_deg"] != exact["route"][1]["bearing_deg"]


# ------------------------------------------------------------------ bad input

BAD_FILES = [
    ("empty.csv", "lsq", "the file is empty"),
    ("binary.csv", "lsq", "not a text CSV file (binary data"),
    ("not_utf8.csv", "lsq", "not a text CSV file (not UTF-8"),
    ("header_only.csv", "lsq", "no data rows"),
    ("missing_column.csv", "lsq", "missing column 'bearing_deg'"),
    ("non_numeric.csv", "lsq", "row 2 (line 3), column obs_x_m: 'east' is not a number (m)"),
    ("blank_value.csv", "lsq", "row 2 (line 3), column bearing_deg: blank value"),
    ("nan_bearing.csv", "lsq", "column bearing_deg: nan deg is not a finite number"),
    ("bearing_out_of_range.csv", "lsq", "column bearing_deg: 360 deg is outside [0, 360) deg"),
    ("ragged_row.csv", "lsq", "row 2 (line 3): has 3 fields, the header has 4"),
    ("time_not_increasing.csv", "lsq", "column t_s: 0 s is not after the previous row's 600 s"),
    ("one_bearing.csv", "lsq", "need at least 2 bearings"),
    ("duplicate_position.csv", "lsq", "rows 2 and 3 have the same observer position"),
    ("parallel.csv", "crossing", "conditioning number u = inf exceeds the limit 1000"),
    ("parallel.csv", "lsq", "conditioning number u = inf exceeds the limit 1000"),
    ("nearly_parallel.csv", "mean", "conditioning number u = 2292 exceeds the limit 1000"),
    ("behind.csv", "crossing", "lies behind the observer of row 2"),
    ("behind.csv", "lsq", "lies behind the observer of row 2"),
    ("behind.csv", "mean", "crosses behind an observer"),
]


def assert_one_line_error(rc, out, err, *fragments):
    assert rc == 2
    assert out == ""
    assert err.startswith("error: ") and err.endswith("\n") and err.count("\n") == 1
    assert "Traceback" not in err
    for fragment in fragments:
        assert fragment in err


@pytest.mark.parametrize(("name", "method", "fragment"), BAD_FILES)
def test_bad_bearing_files_end_with_one_error_line(capsys, tmp_path, name, method, fragment):
    png = tmp_path / "never.png"
    rc = main(["locate", "--bearings", str(MALFORMED / name), "--method", method,
               "--plot", str(png), "--trials", "10", "--seed", "1"])
    out, err = capsys.readouterr()
    assert_one_line_error(rc, out, err, name, fragment)
    assert list(tmp_path.iterdir()) == []  # no output file, no temporary


@pytest.mark.parametrize(("argv", "fragment"), [
    (["locate"], "give --bearings CSV"),
    (["locate", "--bearings", "no/such/file.csv"], "no/such/file.csv: bearings file not found"),
    (["locate", "--bearings", str(PAPER_PAIR), "--d-alpha-deg", "50"],
     "--d-alpha-deg: the bearing error bound must be in (0, 45) deg, got 50.0 deg"),
    (["locate", "--bearings", str(PAPER_PAIR), "--trials", "-1"],
     "--trials: must be in [0, 10000000], got -1"),
    ([*PLAN_PAPER[:2], "--target-x-m", "0", "--target-y-m", "0"],
     "coincides with the target guess"),
    ([*PLAN_PAPER, "--speed-mps", "-5"], "speed_mps: must be > 0 m/s, got -5.0 m/s"),
    ([*PLAN_PAPER, "--legs", "0"], "n_legs: must be an integer in [1, 100000], got 0"),
    ([*PLAN_PAPER, "--min-range-m", "nan"], "min_range_m: must be >= 0 m, got nan m"),
])
def test_bad_options_end_with_one_error_line(capsys, tmp_path, argv, fragment):
    out_csv = tmp_path / "route.csv"
    extra = ["--out", str(out_csv)] if argv[:2] == ["locate", "plan"] else []
    rc = main([*argv, *extra])
    out, err = capsys.readouterr()
    assert_one_line_error(rc, out, err, fragment)
    assert not out_csv.exists()
