"""A thinner bottom for BELLHOP: what ``[propagation] bottom_tolerance_m`` saves and what it moves.

``python -m bench.bench_bottom [--repeats N] [--shelf-runs N]`` writes ``docs/results/bottom.json``.

BELLHOP shortens a ray's step at each segment of the .bty it crosses, and a radial's bottom is
sampled every 100 m (``[grid] range_step_m``, finer than GEBCO's 15" cells), so a 50 km radial
has some 550 segments. With ``bottom_tolerance_m`` the .bty keeps the fewest samples that hold it
within that many metres of every sample (``acoustics.bellhop.radialfiles.thinned_bottom``).
Measured side by side, interleaved, BELLHOP CPU time of each process:

- cost: the build's own runs (a field run and a surface arrivals run per radial) of the
  36-radial area to 50 km that ``bench.bench_radials`` budgets from, every sample against 1 m,
  and 1 m with the ray step doubled (25 -> 50 m); the western-Mediterranean budget of
  ``bench.bench_radials`` from each;
- the tables: shelf-break's 12 radials built from each candidate's runs (and from every sample
  with 6002 arrivals beams: two more than the default of the run with the surface, 6000, a change
  the tables should be indifferent to; since the run's water is mirrored above the surface and
  its default is 3000, twice the default and two more: the rays' own noise), K moved against every
  sample's; and K of the ships (6 and 8 m) from the
  observer against the targets' own runs (``acoustics.builder.truthk``: the source at the target
  with the surface at its end, every sample of the bottom; 2-30 km every 1 km on each radial),
  median |dK| and its mean (the bias) per class and band;
- a tracker on them: the shelf study (shelf-tv, ``--truth tables``: the levels from the very
  tables the trackers read) with the tables of every sample, of 1 m and of 6002 arrivals beams:
  mean RMSE after 5 min and the 90 % range interval's coverage.
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
import tempfile
import types
from pathlib import Path

import numpy as np

import envdata
from acoustics.builder.radial import bottom_on_grid_m, depth_axis_m, plan_radial_image_runs, plan_radial_runs
from acoustics.kcurve import spectral_term_db
from acoustics.surface import SURFACE_ROW_M
from bench.bench_radials import WESTERN_MED_MONTHS, WESTERN_MED_POSITIONS, wide_area
from bench.bench_surface_candidates import moved, run, tables
from bench.harness import Session
from envdata.radials import area_radials

#: (label, bottom tolerance m, ray step m or None for the area's, arrivals beams or None for the area's)
CANDIDATES = (("every sample", 0.0, None, None),
              ("1 m", 1.0, None, None),
              ("0.5 m", 0.5, None, None),
              ("1 m, step 50 m", 1.0, 50.0, None),
              ("every sample, 6002 arrivals beams", 0.0, None, 6002))
#: the candidates whose cost is measured on the 36-radial area
WIDE = ("every sample", "1 m", "1 m, step 50 m")
#: the candidates the shelf study tracks on
STUDY = ("every sample", "1 m", "every sample, 6002 arrivals beams")
TRUTH_RANGES_M = np.arange(2000.0, 30001.0, 1000.0)


def variant(area, tol, step, beams):
    prop = dataclasses.replace(area.propagation, bottom_tolerance_m=tol)
    if step is not None:
        prop = dataclasses.replace(prop, step_m=step)
    if beams is not None:
        prop = dataclasses.replace(prop, surface_image_beams=beams)
    return dataclasses.replace(area, propagation=prop)


def geometry(area):
    """The radials (the settings varied here leave them as they are), the depth axis and the receivers."""
    radials = area_radials(area)
    depth = depth_axis_m(area, radials)
    return radials, depth, np.unique(np.concatenate([depth, [c.depth_m for c in area.classes], [SURFACE_ROW_M]]))


def planned(area, geom):
    """The field runs and the surface's arrivals runs of ``area`` on ``geom`` (`geometry`)."""
    radials, _, receivers = geom
    return plan_radial_runs(area, radials, receivers), plan_radial_image_runs(area, radials, receivers)


def targets_own_k(area, k_grid_bearings, bottom, cache: Path) -> dict:
    """K of each near-surface class from its own runs at TRUTH_RANGES_M on every radial, (N, band), and where."""
    from acoustics.builder.truthk import BellhopTruth

    rng = np.asarray(area.grid.range_m())
    b = np.array([np.interp(TRUTH_RANGES_M, rng, row, left=np.nan, right=np.nan) for row in bottom])
    ib, ir = np.nonzero(np.isfinite(b) & (b > 30.0))
    truth = BellhopTruth(area, cache_dir=cache, workers=2)
    out = {"ib": ib, "ir": ir}
    th = np.radians(np.asarray(k_grid_bearings)[ib])
    r = TRUTH_RANGES_M[ir]
    for ic, cls in enumerate(area.classes):
        if cls.depth_m > 50.0:
            continue
        paths = types.SimpleNamespace(ic=ic, obs_x_m=np.zeros(r.size), obs_y_m=np.zeros(r.size),
                                      obs_depth_m=area.observer.depth_m, x_m=(r * np.sin(th))[None, :],
                                      y_m=(r * np.cos(th))[None, :], target_depth_m=cls.depth_m)
        out[ic] = truth(paths)[0]
    return out


def against_targets(area, k, truth) -> dict:
    """Per near-surface class and band: median |dK| and mean dK (the tables less the targets' own runs)."""
    rng = np.asarray(area.grid.range_m())
    out = {}
    for ic, kt in ((c, v) for c, v in truth.items() if isinstance(c, int)):
        for b, band in enumerate(area.bands):
            # ``k`` holds each radial's band TL at the class depth; K = S - TL (eqs. 12-13)
            tl_table = np.array([np.interp(TRUTH_RANGES_M, rng, k[ic, b, j]) for j in range(k.shape[2])])
            d = (spectral_term_db(area.classes[ic], band) - tl_table[truth["ib"], truth["ir"]]) - kt[:, b]
            ok = np.isfinite(d)
            out[f"{area.classes[ic].name} {band.name}"] = d[ok]
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--shelf-runs", type=int, default=10)
    args = parser.parse_args(argv)
    session = Session("bottom")
    shelf = envdata.load_area("shelf-break")
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        wide = envdata.load_area(wide_area(tmp / "wide", step_deg=10.0, range_max_m=50_000.0))
        shelf_geom, wide_geom = geometry(shelf), geometry(wide)
        radials, depth, receivers = shelf_geom
        bottom = np.stack([bottom_on_grid_m(shelf, rad) for rad in radials])
        plans = {label: planned(variant(shelf, tol, step, beams), shelf_geom) for label, tol, step, beams in CANDIDATES}
        wide_runs = {label: planned(variant(wide, tol, step, beams), wide_geom)
                     for label, tol, step, beams in CANDIDATES if label in WIDE}
        work = {**{f"shelf {label}": fields[0] + images[0] for label, (fields, images) in plans.items()},
                **{f"wide {label}": fields[0] + images[0] for label, (fields, images) in wide_runs.items()}}
        cpu = {name: [] for name in work}
        results = {}

        def once(name):
            total, done = 0.0, []
            for r in work[name]:
                result, seconds = run(r)
                total += seconds
                done.append((r, result))
            cpu[name].append(total)
            if name.startswith("shelf"):
                results[name] = done

        session.interleave({name: (lambda name=name: once(name)) for name in work}, args.repeats)
        cost = {name: statistics.median(v) for name, v in cpu.items()}

        # the tables of each candidate on shelf-break
        made = {}
        for label, (fields, images) in plans.items():
            done = results[f"shelf {label}"]
            field_keys = {r.key for r in fields[0]}
            field_done = [(r, res) for r, res in done if r.key in field_keys]
            image_done = [(r, res) for r, res in done if r.key not in field_keys]
            made[label] = tables(shelf, (field_done, fields[1]), (image_done, images[1]), receivers, depth, bottom)
        base_tl, base_k = made["every sample"]
        truth = targets_own_k(shelf, [rad.bearing_deg for rad in radials], bottom, tmp / "truth")
        shelf_rows = {}
        for label, (tl, k) in made.items():
            row = {"bellhop_cpu_s": round(cost[f"shelf {label}"], 2),
                   "over_every_sample": round(cost[f"shelf {label}"] / cost["shelf every sample"], 3)}
            if label != "every sample":
                row.update(tl_moved=moved(tl, base_tl), k_moved=moved(k, base_k))
            vs = against_targets(shelf, k, truth)
            row["k_against_targets_own_runs"] = {
                key: {"median_abs_db": round(float(np.median(np.abs(d))), 3), "mean_db": round(float(np.mean(d)), 3),
                      "points": int(d.size)} for key, d in vs.items()}
            row["k_against_targets_worst_median_db"] = max(v["median_abs_db"]
                                                           for v in row["k_against_targets_own_runs"].values())
            shelf_rows[label] = row
            session.say(f"shelf-break {label}: BELLHOP CPU", row["bellhop_cpu_s"],
                        f"s ({row['over_every_sample']:.2f} of every sample)")
            if "k_moved" in row:
                session.say(f"shelf-break {label}: K moved, median / p90",
                            f"{row['k_moved']['median_db']} / {row['k_moved']['p90_db']}", "dB")
            session.say(f"shelf-break {label}: ships' K against their own runs, worst median",
                        row["k_against_targets_worst_median_db"], "dB")

        # the western-Mediterranean budget from each candidate's runs on the 36-radial area
        tables_count = WESTERN_MED_POSITIONS * WESTERN_MED_MONTHS
        wide_rows = {}
        for label in WIDE:
            seconds = cost[f"wide {label}"]
            wide_rows[label] = {"bellhop_cpu_s_per_table": round(seconds, 2),
                                "over_every_sample": round(seconds / cost["wide every sample"], 3),
                                "western_med_bellhop_cpu_hours": round(tables_count * seconds / 3600.0)}
            session.say(f"36 radials, {label}: BELLHOP CPU per table", round(seconds, 2),
                        f"s ({wide_rows[label]['over_every_sample']:.2f} of every sample); western Med "
                        f"{wide_rows[label]['western_med_bellhop_cpu_hours']} CPU h of BELLHOP")

        # the shelf study on each candidate's tables
        from tools.studies.shelf import run as shelf_study

        study = {}
        for label in STUDY:
            _, tol, step, beams = next(c for c in CANDIDATES if c[0] == label)
            summary = shelf_study(runs=args.shelf_runs, out_dir=tmp / f"study {label}", truth="tables", workers=2,
                                  area=variant(shelf, tol, step, beams))
            study[label] = {
                "mean_rmse_after_5min_m": {k: round(v) for k, v in summary["mean_rmse_after_5min_m"].items()},
                "range_coverage_90": {k: v["range"]["coverage_90"]
                                      for k, v in summary["calibration_after_late_min"].items()}}
            session.say(f"shelf study on {label}: ML / PF on the bearing tables, RMSE after 5 min",
                        f"{study[label]['mean_rmse_after_5min_m']['ml_bearing']} / "
                        f"{study[label]['mean_rmse_after_5min_m']['rpf_bearing']}", "m")
            session.say(f"shelf study on {label}: PF range coverage (90 % interval)",
                        study[label]["range_coverage_90"]["rpf_bearing"], "")
    session.write(repeats=args.repeats, shelf_break=shelf_rows, wide_36_radials=wide_rows, shelf_study=study,
                  shelf_study_runs=args.shelf_runs, candidates=[list(c) for c in CANDIDATES],
                  truth_ranges_m=TRUTH_RANGES_M.tolist())
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
