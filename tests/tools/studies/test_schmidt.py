"""The Schmidt et al. worked example (docs/results/locate.json), checked by other routes."""

from __future__ import annotations

import json
import math

import numpy as np
from numpy.testing import assert_allclose

from tools.studies import schmidt
from tracker import locate as loc


def test_run_writes_the_table_and_its_figures_agree_with_the_geometry(tmp_path):
    out = tmp_path / "results" / "locate.json"
    returned = schmidt.run(out, seed=7, trials=400, expectation_trials=20_000)
    data = json.loads(out.read_text())
    assert data == json.loads(json.dumps(returned))
    assert data["inputs"]["seed"] == 7 and data["inputs"]["trials"] == 400
    assert list(data["rules"]) == ["eq23", "eq17"]
    x0, y0 = data["inputs"]["target"]
    d = data["inputs"]["d_alpha_deg"]
    for rule, r in data["rules"].items():
        (ax, ay), (bx, by) = r["observer"]
        a1, a2 = r["bearing_deg"]
        assert_allclose(math.hypot(bx - ax, by - ay), data["inputs"]["leg"], rtol=1e-12)
        # the bearings are those seen from the two points at the target
        assert_allclose(loc.bearing_to_deg([ax, bx], [ay, by], x0, y0), [a1, a2], atol=1e-9)
        # u by the SVD of P, |P| as its determinant
        p, _ = loc.bearing_system([ax, bx], [ay, by], [a1, a2])
        assert_allclose(loc.conditioning_number([a1, a2]), r["u"], rtol=1e-9)
        assert_allclose(abs(np.linalg.det(p)), r["determinant"], rtol=1e-9)
        # d13 and d24: distances between crossings of the extreme bearing lines
        def vertex(e1, e2, ax=ax, ay=ay, a1=a1, bx=bx, by=by, a2=a2):
            vx, vy, *_ = loc.crossing_point(ax, ay, a1 + e1, bx, by, a2 + e2)
            return np.array([vx, vy])

        v1, v2, v3, v4 = vertex(d, d), vertex(d, -d), vertex(-d, -d), vertex(-d, d)
        assert_allclose(np.hypot(*(v1 - v3)), r["d13"], rtol=1e-9)
        assert_allclose(np.hypot(*(v2 - v4)), r["d24"], rtol=1e-9)
        assert_allclose(r["vertices"], [v1, v2, v3, v4], atol=1e-9)
        assert_allclose(r["ratio"], r["d24"] / r["d13"], rtol=1e-12)
        assert_allclose(r["area_diagonals"], r["d13"] * r["d24"] / 2, rtol=1e-12)
        # the area by clipping the two bearing wedges, not by the shoelace of the vertices
        wedges = loc.error_polygon([ax, bx], [ay, by], x0, y0, d_alpha_deg=d)
        assert_allclose(wedges.area_m2, r["area"], rtol=1e-9)
        assert r["area"] < r["area_diagonals"] and 80.0 < r["diagonals_angle_deg"] < 90.0
        # the formulas approximate the exact figures
        assert abs(r["d13_eq25"] / r["d13"] - 1) < 1e-3
        assert abs(r["d24_eq27"] / r["d24"] - 1) < 0.02
        # Monte Carlo: every trial gives a fix, the sample mean lies within 4 standard errors
        # of the expectation, and the bias is away from the observer
        mc, ex = r["monte_carlo"], r["expectation"]
        assert mc["fixes"] == 400 and ex["fixes"] == 20_000 and mc["inside_fraction"] >= 0.99
        for k in range(2):
            se = math.hypot(mc["standard_error"][k], ex["standard_error"][k])
            assert abs(mc["mean"][k] - ex["mean"][k]) < 4 * se, (rule, k)
            assert_allclose(mc["standard_error"][k], ex["standard_error"][k] * math.sqrt(50),
                            rtol=1e-12)
        assert ex["bias"][0] > 0 and ex["bias"][1] > 0
    # the eq23 first leg closes the range: its second bearing turns more, its d13 is shorter
    eq23, eq17 = data["rules"]["eq23"], data["rules"]["eq17"]
    assert eq23["delta_deg"] > eq17["delta_deg"] and eq23["d13"] < eq17["d13"]


def test_the_same_seed_gives_the_same_file(tmp_path):
    runs = {name: schmidt.run(tmp_path / f"{name}.json", seed=seed, trials=50,
                              expectation_trials=500)
            for name, seed in (("a", 3), ("b", 3), ("c", 4))}
    assert (tmp_path / "a.json").read_text() == (tmp_path / "b.json").read_text()
    mean = {name: r["rules"]["eq23"]["monte_carlo"]["mean"] for name, r in runs.items()}
    assert mean["a"] != mean["c"]
    assert "eq23" in schmidt.table(runs["a"])


def test_main_writes_the_file_and_prints_the_table(tmp_path, capsys):
    out = tmp_path / "locate.json"
    assert schmidt.main(["--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "d24 exact" in text and f"wrote {out}" in text
    assert json.loads(out.read_text())["inputs"]["expectation_trials"] == 1_000_000
