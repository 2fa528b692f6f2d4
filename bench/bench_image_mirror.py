"""The surface's arrivals run with the water mirrored above the surface: cost, convergence in
beams, and K of the surface ships against references that do not share its approximation.

``python -m bench.bench_image_mirror [--repeats N]`` writes ``docs/results/image-mirror.json``.

Each variant is one arrivals run per radial, made as the build makes it
(``acoustics.builder.radial.plan_radial_image_runs``, the beams set) and reduced as the build
reduces it (``acoustics.builder.surfaceimage.image_tl_db``): ``mirrored``, the water mirrored
above the surface, each row the sum of its arrivals at z and at -z with their Lloyd factors.
The result file in docs/results was made at commit 50757f5, the last that also had the run it
replaced, measured beside it in the same turns: ``with the surface``, the run with the sea
surface whose arrivals were paired with their surface twins, a twin the hat beams' truncation at
the surface had cut restored (6000 beams by default; ``git show 50757f5:bench/bench_image_mirror.py``).

Figures:

- BELLHOP CPU of each variant's 12 shelf-break runs (the processes' own; median of the repeats);
- convergence: each variant's near-surface rows against the same method with `FINEST` beams,
  |dTL| median and p90 per cell and over 1 km of range (intensity averaged over ten cells), and
  the signed mean over 1 km (positive: lossier than the finer fan);
- shelf-break truth: K of the 6-8 m classes (S - TL at the class's row) against BELLHOP run
  from the target along each true path (``bench.bench_bottom.targets_own_k``:
  ``acoustics.builder.truthk.BellhopTruth``, the source at the ship with its Lloyd pattern, the
  observer the receiver; what ``simulate --truth bellhop`` hears), targets on every third radial
  every 1 km from 2 to 30 km where the water is deeper than 30 m (the file at 50757f5 took every
  target whose own water the run from it could take); per class and band |dK| median, p90 and
  mean (positive: the table louder);
- ocean-deep reciprocity: the check in ``make test``
  (``bench.crosscheck.surface.reciprocity_case``) with each variant's beams.
"""

from __future__ import annotations

import argparse
import dataclasses
import resource
import statistics

import numpy as np

import envdata
from acoustics.bellhop.runner import run_env
from acoustics.builder.radial import bottom_on_grid_m, depth_axis_m, plan_radial_image_runs
from acoustics.builder.surfaceimage import image_tl_db
from acoustics.surface import SURFACE_ROW_M
from bench.bench_bottom import against_targets, targets_own_k
from bench.crosscheck.surface import reciprocity_case, stats
from bench.harness import REPO, Session
from envdata.radials import area_radials

#: (label, beams); the first is the build's default.
VARIANTS = (("mirrored, 3000", 3000), ("mirrored, 6000", 6000), ("mirrored, 12000", 12000))
#: The fan the others' convergence is measured against.
FINEST = 12000
#: Compared with the references (the finest fan only converges).
COMPARED = tuple(label for label, beams in VARIANTS if beams < FINEST)
#: Cells averaged for the 1 km figures (the grid's 100 m range step).
CELLS_PER_KM = 10
#: Targets of the truth comparison: every this many radials.
TRUTH_RADIAL_STEP = 3
TRUTH_CACHE = REPO / "out" / "bench-image-mirror" / "truth-runs"


def child_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_all(area, radials, receivers, beams) -> tuple[np.ndarray, np.ndarray, float]:
    """Every radial's near-surface TL (radial, class, band, row, range), the rows' depths, and
    BELLHOP's CPU seconds."""
    area = dataclasses.replace(area, propagation=dataclasses.replace(area.propagation, surface_image_beams=beams))
    runs, where = plan_radial_image_runs(area, radials, receivers)
    runs = sorted(runs, key=lambda r: where[r.key][0])
    before = child_cpu()
    tl = np.stack([image_tl_db(run_env(r.env, files=dict(r.files), timeout_s=r.timeout_s).arrivals[0], r.image)
                   for r in runs])
    return tl, np.asarray(runs[0].image.receiver_depth_m), child_cpu() - before


def class_rows(area, tl, rows_m) -> np.ndarray:
    """TL at each class's depth, (class, band, radial, range) (NaN for a class beyond the rows)."""
    out = np.full((len(area.classes), len(area.bands), tl.shape[0], tl.shape[-1]), np.nan)
    for ic, cls in enumerate(area.classes):
        at = np.flatnonzero(np.isclose(rows_m, cls.depth_m))
        if at.size:
            out[ic] = np.moveaxis(tl[:, ic, :, at[0]], 0, 1)
    return out


def km_average(tl_db: np.ndarray) -> np.ndarray:
    intensity = 10.0 ** (-np.asarray(tl_db, dtype=float) / 10.0)
    kernel = np.ones(CELLS_PER_KM) / CELLS_PER_KM
    mean = np.apply_along_axis(lambda x: np.convolve(x, kernel, mode="valid"), -1, intensity)
    return -10.0 * np.log10(np.maximum(mean, 1e-300))


def converged(tl: np.ndarray, finest: np.ndarray, cap_db: float) -> dict:
    lit = (tl < cap_db) & (finest < cap_db)
    cell = np.abs(tl - finest)[lit]
    km, km_f = km_average(tl), km_average(finest)
    d = (km - km_f)[(km < cap_db) & (km_f < cap_db)]
    return {"cell_median_db": round(float(np.median(cell)), 3), "cell_p90_db": round(float(np.percentile(cell, 90)), 3),
            "km_median_db": round(float(np.median(np.abs(d))), 3),
            "km_p90_db": round(float(np.percentile(np.abs(d), 90)), 3), "km_mean_db": round(float(np.mean(d)), 3)}


def worst(by_case: dict) -> dict:
    return {"worst_median_db": max(s["median_db"] for s in by_case.values()),
            "mean_range_db": [min(s["mean_db"] for s in by_case.values()), max(s["mean_db"] for s in by_case.values())]}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=2)
    args = parser.parse_args(argv)
    session = Session("image-mirror")
    area = envdata.load_area("shelf-break")
    radials = area_radials(area)
    receivers = np.unique(np.concatenate([depth_axis_m(area, radials), [c.depth_m for c in area.classes],
                                          [SURFACE_ROW_M]]))
    cpu = {label: [] for label, _ in VARIANTS}
    tables: dict[str, np.ndarray] = {}
    rows_m = None

    def once(label, beams):
        nonlocal rows_m
        tl, rows_m, seconds = run_all(area, radials, receivers, beams)
        cpu[label].append(seconds)
        tables[label] = tl  # BELLHOP is deterministic: every repeat gives the same

    session.interleave({label: (lambda label=label, beams=beams: once(label, beams)) for label, beams in VARIANTS},
                       args.repeats)
    first = statistics.median(cpu[VARIANTS[0][0]])
    finest = next(label for label, beams in VARIANTS if beams == FINEST)
    out = {}
    for label, beams in VARIANTS:
        seconds = statistics.median(cpu[label])
        row = {"beams": beams, "runs": len(radials), "bellhop_cpu_s": round(seconds, 2),
               "cpu_runs_s": [round(s, 2) for s in cpu[label]], "of_before": round(seconds / first, 3)}
        if beams < FINEST:
            row["against_finest"] = converged(tables[label], tables[finest], area.propagation.tl_max_db)
        out[label] = row
    picked = radials[::TRUTH_RADIAL_STEP]
    bottom = np.stack([bottom_on_grid_m(area, rad) for rad in picked])
    own = targets_own_k(area, [rad.bearing_deg for rad in picked], bottom, TRUTH_CACHE)
    truth = {label: {key: stats(d) for key, d in against_targets(
        area, class_rows(area, tables[label][::TRUTH_RADIAL_STEP], rows_m), own).items()} for label in COMPARED}
    reciprocity = {label: reciprocity_case(image_beams=beams) for label, beams in VARIANTS if label in COMPARED}
    for label, row in out.items():
        text = f"{row['bellhop_cpu_s']:.1f} s ({row['of_before']:.2f} of the first row's)"
        if "against_finest" in row:
            c = row["against_finest"]
            text += (f"; against {FINEST} beams over 1 km: {c['km_median_db']} / {c['km_p90_db']} "
                     f"(mean {c['km_mean_db']:+})")
        session.say(label, text, "BELLHOP CPU; |dTL| median / p90, dB")
    for label in COMPARED:
        t, rc = worst(truth[label]), worst(reciprocity[label])
        session.say(f"{label}: shelf-break ships' K against the true paths", t["worst_median_db"],
                    f"dB, worst class and band median; means {t['mean_range_db'][0]:+} to {t['mean_range_db'][1]:+} dB")
        session.say(f"{label}: ocean-deep ships' K against their own runs", rc["worst_median_db"],
                    f"dB, worst class and band median (bound 0.5); means {rc['mean_range_db'][0]:+} to "
                    f"{rc['mean_range_db'][1]:+} dB")
    session.write(repeats=args.repeats, area="shelf-break", radials=len(radials), finest_beams=FINEST,
                  variants=out, truth=truth, reciprocity=reciprocity,
                  truth_targets={"radial_step": TRUTH_RADIAL_STEP, "ranges_km": [2, 30, 1]})
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
