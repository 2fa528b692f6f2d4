"""The worked example of Schmidt et al., "Bearing Errors in Passive Sonar Stationary Target
Location" (the paper's Figs. 8 and 9).

An observer at the origin, a stationary target at x0 = y0 = 10, a leg VT = 3 between the first
two bearings (the first is 45 deg), bearing errors within D_alpha = 1 deg (the captions say 10;
the printed numbers are for 1). For each first-leg rule, ``eq23`` (course perpendicular to the
anticipated second bearing, R1 known) and ``eq17`` (perpendicular to the first bearing), `run`
computes with `tracker.locate` the second bearing, u (eq. 11), |P| (eq. 10), the error
quadrilateral (d13, d24, their ratio and its area, exactly and by eqs. 25-28), the mean fix of
``trials`` Monte Carlo trials (eq. 29, ``default_rng(seed)``, as ``tmakit locate plan --trials N
--seed S`` does), its expectation from ``expectation_trials`` trials, and the share of trial
fixes inside the quadrilateral, and writes them as JSON.

The library works in metres: the example runs at 1 unit = `UNIT_M` m (VT = 5 m/s x 600 s, as in
docs/locate.md) and the file gives lengths in the paper's units (areas in square units).

``python -m tools.studies.schmidt --out docs/results/locate.json`` writes the file that
docs/locate.md quotes.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

from acoustics.grid.formats import RESULT_FORMAT
from envdata.files import atomic_path
from tracker import locate as loc

UNIT_M = 1000.0
TARGET = (10.0, 10.0)       # x0, y0, units
SPEED_MPS, LEG_S = 5.0, 600.0  # VT = 3000 m = 3 units
D_ALPHA_DEG = 1.0
RULES = ("eq23", "eq17")
#: Tolerance of "inside the quadrilateral", m (the one `tmakit locate plan` uses).
INSIDE_TOL_M = 1e-6
#: The paper's printed figures for the eq23 case, quoted for comparison (not computed).
PAPER = {"d13_eq25": 0.4936, "d24": 4.6992, "d24_eq27": 4.6662, "area": "about 1.16",
         "mc_mean": [10.0531, 10.0385], "inside": "practically all"}


def _monte_carlo(rule: str, trials: int, rng: np.random.Generator) -> loc.MonteCarlo:
    return loc.monte_carlo_first_leg(target_x_m=TARGET[0] * UNIT_M, target_y_m=TARGET[1] * UNIT_M,
                                     leg_m=SPEED_MPS * LEG_S, d_alpha_deg=D_ALPHA_DEG,
                                     n_trials=trials, rng=rng, rule=rule)


def _mean(mc: loc.MonteCarlo, std_trials: int) -> dict:
    """Mean fix (eq. 29) in units, and the standard error of a ``std_trials``-trial mean."""
    return {"trials": mc.n_trials, "fixes": int(mc.x_m.size),
            "mean": [mc.mean_x_m / UNIT_M, mc.mean_y_m / UNIT_M],
            "standard_error": [float(np.std(v, ddof=1)) / UNIT_M / math.sqrt(std_trials)
                               for v in (mc.x_m, mc.y_m)]}


def first_pair(rule: str, *, seed: int, trials: int, expectation_trials: int) -> dict:
    """The table's figures for one first-leg rule, lengths in units."""
    tx, ty = TARGET[0] * UNIT_M, TARGET[1] * UNIT_M
    route = loc.plan_route(target_x_m=tx, target_y_m=ty, speed_mps=SPEED_MPS, leg_s=LEG_S,
                           n_legs=1, rule=rule)
    reg = loc.error_region(route.obs_x_m, route.obs_y_m, tx, ty, d_alpha_deg=D_ALPHA_DEG)
    mc = _monte_carlo(rule, trials, np.random.default_rng(seed))
    big = _monte_carlo(rule, expectation_trials, np.random.default_rng([seed, 1]))
    sample = _mean(mc, trials)
    # the spread of the large sample gives the standard error of a `trials`-trial mean
    sample["standard_error"] = _mean(big, trials)["standard_error"]
    sample["inside_fraction"] = float(np.mean(reg.contains(mc.x_m, mc.y_m, tol_m=INSIDE_TOL_M)))
    expectation = _mean(big, expectation_trials)
    expectation["bias"] = [m - t for m, t in zip(expectation["mean"], TARGET)]
    return {
        "observer": [[float(x) / UNIT_M, float(y) / UNIT_M]
                     for x, y in zip(route.obs_x_m, route.obs_y_m)],
        "bearing_deg": [float(b) for b in route.bearing_deg],
        "delta_deg": reg.delta_deg,
        "u": float(route.u[0]), "determinant": float(route.determinant[0]),
        "vertices": (reg.vertices_m / UNIT_M).tolist(),
        "d13": reg.d13_m / UNIT_M, "d13_eq25": reg.d13_eq25_m / UNIT_M,
        "d24": reg.d24_m / UNIT_M, "d24_eq26": reg.d24_eq26_m / UNIT_M,
        "d24_eq27": reg.d24_eq27_m / UNIT_M,
        "ratio": reg.ratio, "ratio_eq28": reg.ratio_eq28,
        "area": reg.area_m2 / UNIT_M ** 2, "area_diagonals": reg.area_diagonals_m2 / UNIT_M ** 2,
        # area = d13 d24 sin(angle) / 2 for any convex quadrilateral: the diagonals' crossing angle
        "diagonals_angle_deg": math.degrees(math.asin(min(reg.area_m2 / reg.area_diagonals_m2,
                                                          1.0))),
        "monte_carlo": sample, "expectation": expectation,
    }


def run(out_path, seed: int = 12345, trials: int = 1000,
        expectation_trials: int = 1_000_000) -> dict:
    """Compute the example for both rules and write it as JSON to ``out_path`` (atomically)."""
    result = {
        "paper": 'Schmidt et al., "Bearing Errors in Passive Sonar Stationary Target Location"',
        "written_by": f"tools.studies.schmidt.run(seed={seed}, trials={trials}, "
                      f"expectation_trials={expectation_trials})",
        "numpy": np.__version__,
        "inputs": {"unit_m": UNIT_M, "target": list(TARGET), "start": [0.0, 0.0],
                   "speed_mps": SPEED_MPS, "leg_s": LEG_S, "leg": SPEED_MPS * LEG_S / UNIT_M,
                   "d_alpha_deg": D_ALPHA_DEG, "side": "port", "seed": seed, "trials": trials,
                   "trials_rng": f"numpy.random.default_rng({seed})",
                   "expectation_trials": expectation_trials,
                   "expectation_rng": f"numpy.random.default_rng([{seed}, 1])",
                   "steer_on_measured": True, "inside_tol_m": INSIDE_TOL_M},
        "units": "lengths in units of unit_m metres, areas in square units, angles in deg",
        "rules": {rule: first_pair(rule, seed=seed, trials=trials,
                                   expectation_trials=expectation_trials) for rule in RULES},
        "paper_eq23": PAPER,
    }
    out = Path(out_path)
    out.parent.mkdir(parents=True, exist_ok=True)
    result = {"tmakit_format": RESULT_FORMAT, **result}
    with atomic_path(out) as tmp:
        tmp.write_text(json.dumps(result, indent=1) + "\n")
    return result


def table(result: dict) -> str:
    """The figures as a short text table, one column per rule."""
    rows = [("second bearing, deg", lambda r: f"{r['bearing_deg'][1]:.3f}"),
            ("u / |P|", lambda r: f"{r['u']:.3f} / {r['determinant']:.4f}"),
            ("d13 eq.25 / exact", lambda r: f"{r['d13_eq25']:.4f} / {r['d13']:.5f}"),
            ("d24 exact", lambda r: f"{r['d24']:.4f}"),
            ("d24 eq.26 / eq.27", lambda r: f"{r['d24_eq26']:.4f} / {r['d24_eq27']:.4f}"),
            ("d24/d13 exact / eq.28", lambda r: f"{r['ratio']:.3f} / {r['ratio_eq28']:.3f}"),
            ("area shoelace / d13*d24/2",
             lambda r: f"{r['area']:.4f} / {r['area_diagonals']:.4f}"),
            ("mean of trials", lambda r: "({:.4f}, {:.4f})".format(*r["monte_carlo"]["mean"])),
            ("  its standard error", lambda r: "({:.3f}, {:.3f})".format(
                *r["monte_carlo"]["standard_error"])),
            ("expected mean", lambda r: "({:.4f}, {:.4f})".format(*r["expectation"]["mean"])),
            ("inside the quadrilateral",
             lambda r: f"{100 * r['monte_carlo']['inside_fraction']:.1f} %")]
    rules = result["rules"]
    lines = [f"{'':26}" + "".join(f"{name:>22}" for name in rules)]
    lines += [f"{label:26}" + "".join(f"{fmt(r):>22}" for r in rules.values())
              for label, fmt in rows]
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m tools.studies.schmidt",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True, help="JSON file to write")
    args = parser.parse_args(argv)
    print(table(run(args.out)))
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
