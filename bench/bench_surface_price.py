"""The surface's price: what the arrivals run that puts the surface at a target that is the
receiver costs beside the field runs, and what cheaper arrivals runs would give up.

``python -m bench.bench_surface_price [--repeats N]`` writes ``docs/results/surface-price.json``.

A table from the observer with the surface costs the incoherent build's field run per radial and
one mirrored arrivals run (``acoustics.builder.imageruns``). Issue 37 asks for the pair at no
more than 1.5x the field runs, so the arrivals run at no more than half of them. On shelf-break's
12 radials, in one run, interleaved:

- the field runs (``plan_radial_runs``): the incoherent build's BELLHOP time;
- ``mirrored, N``: the build's method with N beams (the default is ``Propagation.image_beams``,
  3000 here): each row the sum of its arrivals at z and -z with their Lloyd factors;
- ``ratio, N``: the field run's band TL at each row with the Lloyd factor's intensity-weighted
  mean from an N-beam run put on it, TL_field - 10 log10(sum I G / sum I) over the same
  arrivals. The ratio of two sums over the same beams converges with few beams, where the sums
  themselves do not; the level is the field run's.

Figures per variant: BELLHOP CPU of its arrivals runs over the field runs' (both the processes'
own, medians of the repeats), the near-surface rows against ``mirrored, FINEST`` over 1 km of
range, and K of the 6-8 m classes against BELLHOP run from the target along each true path
(``bench.bench_image_mirror``'s truth, its cache shared). The file says what would meet the
1.5x and what it would give up; nothing here changes the build.
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics

import numpy as np

import envdata
from acoustics.bellhop.runner import run_env
from acoustics.bellhop.shdfile import tl_from_pressure
from acoustics.builder.bandruns import band_tl_from_runs
from acoustics.builder.radial import bottom_on_grid_m, depth_axis_m, plan_radial_image_runs, plan_radial_runs
from acoustics.builder.surfaceimage import image_sums, intensity_tl_db
from acoustics.surface import SURFACE_ROW_M
from bench.bench_bottom import against_targets, targets_own_k
from bench.bench_image_mirror import TRUTH_CACHE, TRUTH_RADIAL_STEP, child_cpu, class_rows, converged
from bench.crosscheck.surface import stats
from bench.harness import Session
from envdata.radials import area_radials

#: Beams of the arrivals runs measured; each gives a ``mirrored`` and a ``ratio`` variant.
BEAMS = (250, 500, 750, 1500, 3000)
#: The fan the others are measured against.
FINEST = 12000
#: The build's default beams here (``Propagation.image_beams`` of shelf-break).
DEFAULT = 3000
#: Issue 37's bound on the pair (field and arrivals runs) over the field runs alone.
TARGET = 1.5


def field_rows(area, radials, receivers) -> tuple[dict, float]:
    """Each radial's band TL (class, band, depth, range) from its field run, and BELLHOP's CPU."""
    runs, where = plan_radial_runs(area, radials, receivers)
    before, out = child_cpu(), {}
    for run in runs:
        j, f = where[run.key]
        p = run_env(run.env, files=dict(run.files), timeout_s=run.timeout_s).field.pressure[0]
        tl = tl_from_pressure(p, area.propagation.tl_max_db)
        out[j] = np.stack([np.stack([band_tl_from_runs(area, cls, band, {f: tl}) for band in area.bands])
                           for cls in area.classes])
    return out, child_cpu() - before


def arrivals_sums(area, radials, receivers, beams) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Every radial's near-surface intensities with and without the Lloyd factor (radial, class,
    band, row, range), the rows' indices among ``receivers``, and BELLHOP's CPU."""
    area = dataclasses.replace(area, propagation=dataclasses.replace(area.propagation, surface_image_beams=beams))
    runs, where = plan_radial_image_runs(area, radials, receivers)
    runs = sorted(runs, key=lambda r: where[r.key][0])
    before, lloyd, plain = child_cpu(), [], []
    for run in runs:
        result = run_env(run.env, files=dict(run.files), timeout_s=run.timeout_s)
        lo, pl = image_sums(result.arrivals[0], run.image, plain=True)
        lloyd.append(lo)
        plain.append(pl)
    return np.stack(lloyd), np.stack(plain), where[runs[0].key][1], child_cpu() - before


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=2)
    args = parser.parse_args(argv)
    session = Session("surface-price")
    area = envdata.load_area("shelf-break")
    cap = area.propagation.tl_max_db
    radials = area_radials(area)
    receivers = np.unique(np.concatenate([depth_axis_m(area, radials), [c.depth_m for c in area.classes],
                                          [SURFACE_ROW_M]]))
    cpu: dict[str, list[float]] = {}
    sums: dict[int, tuple] = {}
    field: dict = {}

    def fields():
        tl, seconds = field_rows(area, radials, receivers)
        field.update(tl)
        cpu.setdefault("field", []).append(seconds)

    def arrivals(beams):
        lloyd, plain, rows, seconds = arrivals_sums(area, radials, receivers, beams)
        sums[beams] = (lloyd, plain, rows)  # BELLHOP is deterministic: every repeat gives the same
        cpu.setdefault(beams, []).append(seconds)

    session.interleave({"field": fields, **{f"arrivals {b}": (lambda b=b: arrivals(b)) for b in (*BEAMS, FINEST)}},
                       args.repeats)
    rows = sums[FINEST][2]
    rows_m = receivers[rows]
    field_tl = np.stack([field[j][:, :, rows] for j in range(len(radials))])

    def mirrored(b):
        return intensity_tl_db(sums[b][0], cap)

    def ratio(b):
        lloyd, plain, _ = sums[b]
        mean_g = np.where(plain > 0.0, lloyd / np.maximum(plain, 1e-300), 1.0)
        return np.minimum(field_tl - 10.0 * np.log10(np.maximum(mean_g, 1e-30)), cap)

    finest = mirrored(FINEST)
    picked = radials[::TRUTH_RADIAL_STEP]
    bottom = np.stack([bottom_on_grid_m(area, rad) for rad in picked])
    own = targets_own_k(area, [rad.bearing_deg for rad in picked], bottom, TRUTH_CACHE)
    field_s = statistics.median(cpu["field"])
    variants = {}
    for kind, make in (("mirrored", mirrored), ("ratio", ratio)):
        for b in (*BEAMS, FINEST):
            if kind == "ratio" and b == FINEST:
                continue
            tl = make(b)
            seconds = statistics.median(cpu[b])
            truth = {key: stats(d) for key, d in against_targets(
                area, class_rows(area, tl[::TRUTH_RADIAL_STEP], rows_m), own).items()}
            row = {"beams": b, "arrivals_cpu_s": round(seconds, 2), "arrivals_over_field": round(seconds / field_s, 3),
                   "pair_over_field": round(1.0 + seconds / field_s, 3), "truth": truth,
                   "truth_worst_median_db": max(s["median_db"] for s in truth.values()),
                   "truth_mean_range_db": [min(s["mean_db"] for s in truth.values()),
                                           max(s["mean_db"] for s in truth.values())]}
            if not (kind == "mirrored" and b == FINEST):
                row["against_finest"] = converged(tl, finest, cap)
            variants[f"{kind}, {b}"] = row
    session.say("field runs", round(field_s, 2), "s BELLHOP CPU, 12 radials (median)", runs=cpu["field"])
    for label, row in variants.items():
        c = row.get("against_finest", {})
        session.say(label, row["pair_over_field"],
                    f"x the field runs with its arrivals runs; truth worst median {row['truth_worst_median_db']} dB, "
                    f"means {row['truth_mean_range_db'][0]:+} to {row['truth_mean_range_db'][1]:+} dB; against "
                    f"{FINEST} beams over 1 km {c.get('km_median_db')} / {c.get('km_p90_db')} dB")
    session.write(repeats=args.repeats, area="shelf-break", radials=len(radials), finest_beams=FINEST,
                  default_beams=DEFAULT, target_pair_over_field=TARGET, field_cpu_s=round(field_s, 2),
                  rows_m=[float(z) for z in rows_m], variants=variants,
                  truth_targets={"radial_step": TRUTH_RADIAL_STEP, "ranges_km": [2, 30, 1]})
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
