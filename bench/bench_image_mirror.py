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
  from the target along each true path (``acoustics.builder.truthk.BellhopTruth``: the source at
  the ship with its Lloyd pattern, the observer the receiver; what ``simulate --truth bellhop``
  hears), targets on every third radial every 1 km from 2 to 30 km where the table has water;
  per class and band |dK| median, p90 and mean (positive: the table louder);
- ocean-deep reciprocity: the same K from one radial of ocean-deep (to 40 km) against its flat
  grid, whose K comes from the targets' own runs (the check in ``make test``).
"""

from __future__ import annotations

import argparse
import dataclasses
import resource
import statistics

import numpy as np

import acoustics
import envdata
from acoustics.bellhop.runner import run_env
from acoustics.builder.radial import bottom_on_grid_m, depth_axis_m, plan_radial_image_runs
from acoustics.builder.surfaceimage import image_tl_db
from acoustics.kcurve import spectral_term_db
from acoustics.surface import SURFACE_ROW_M
from bench.harness import REPO, Session
from envdata.radials import area_radials

#: (label, mirrored, beams); the first is the build's default.
VARIANTS = (
    ("mirrored, 3000", True, 3000),
    ("mirrored, 6000", True, 6000),
    ("mirrored, 12000", True, 12000),
)
#: The fan each method's convergence is measured against.
FINEST = 12000
#: Compared with the references (the finest fans only converge).
COMPARED = tuple(label for label, _, beams in VARIANTS if beams < FINEST)
#: Cells averaged for the 1 km figures (the grid's 100 m range step).
CELLS_PER_KM = 10
#: Targets of the truth comparison: every this many radials, at these ranges (m).
TRUTH_RADIAL_STEP, TRUTH_RANGES_M = 3, np.arange(2000.0, 30001.0, 1000.0)
TRUTH_CACHE = REPO / "out" / "bench-image-mirror" / "truth-runs"


def with_beams(area, beams):
    return dataclasses.replace(area, propagation=dataclasses.replace(area.propagation, surface_image_beams=beams))


def child_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def image_runs(area, radials, receivers, mirrored, beams):
    assert mirrored, "the run with the surface is gone since commit 50757f5"
    runs, where = plan_radial_image_runs(with_beams(area, beams), radials, receivers)
    return [(where[r.key][0], r) for r in runs]


def run_all(runs) -> tuple[dict[int, np.ndarray], float]:
    """Each radial's near-surface TL (class, band, row, range) and BELLHOP's CPU seconds."""
    before = child_cpu()
    out = {j: image_tl_db(run_env(r.env, files=dict(r.files), timeout_s=r.timeout_s).arrivals[0], r.image)
           for j, r in runs}
    return out, child_cpu() - before


def k_rows(area, runs, tl) -> dict[int, np.ndarray]:
    """Per radial, K (class, band, range) of each class within the surface's reach at its row (NaN
    for the others)."""
    out = {}
    for j, r in runs:
        rows = np.asarray(r.image.receiver_depth_m)
        k = np.full(tl[j].shape[:2] + tl[j].shape[3:], np.nan)
        for ic, cls in enumerate(area.classes):
            at = np.flatnonzero(np.isclose(rows, cls.depth_m))
            if at.size:
                for ib, band in enumerate(area.bands):
                    k[ic, ib] = spectral_term_db(cls, band) - tl[j][ic, ib, at[0]]
        out[j] = k
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


def stats(d: np.ndarray) -> dict:
    d = d[np.isfinite(d)]
    return {"median_db": round(float(np.median(np.abs(d))), 2), "p90_db": round(float(np.percentile(np.abs(d), 90)), 2),
            "mean_db": round(float(np.mean(d)), 2), "n": int(d.size)}


def truth_case(area, radials, k_by_variant: dict[str, dict[int, np.ndarray]]) -> dict:
    """K of the ships from each variant's rows against BELLHOP along the true path."""
    from acoustics.builder.truthk import BellhopTruth, _Path
    from envdata.errors import AreaError

    truth = BellhopTruth(area, cache_dir=TRUTH_CACHE, workers=2)
    rng = area.grid.range_m()
    out: dict[str, dict] = {label: {} for label in k_by_variant}
    for ic, cls in enumerate(area.classes):
        if not np.isfinite(next(iter(k_by_variant.values()))[0][ic]).any():
            continue  # not within the surface's reach
        diffs = {label: [] for label in k_by_variant}
        for j in range(0, len(radials), TRUTH_RADIAL_STEP):
            bottom = bottom_on_grid_m(area, radials[j])
            b = np.radians(radials[j].bearing_deg)
            for r in TRUTH_RANGES_M:
                ir = int(np.argmin(np.abs(rng - r)))
                if not bottom[ir] > cls.depth_m + 1.0:
                    continue
                path = _Path(float(r * np.sin(b)), float(r * np.cos(b)), 0.0, 0.0, float(cls.depth_m),
                             float(area.observer.depth_m))
                try:
                    kt = truth.k_of_paths(ic, [path])[path]
                except AreaError:  # the target's own water too shallow for the run from it
                    continue
                for label, k in k_by_variant.items():
                    diffs[label].append(k[j][ic, :, ir] - kt)
        for label, d in diffs.items():
            d = np.array(d)
            for ib, band in enumerate(area.bands):
                out[label][f"{cls.name} {band.name}"] = stats(d[:, ib])
    return out


def reciprocity_case(variants) -> dict:
    """ocean-deep to 40 km (the ``make test`` check's settings): K of the 6-8 m classes from one
    radial's rows against the flat grid's, from the targets' own runs (beyond 2 km)."""
    from bench.crosscheck.surface import _area

    doc = envdata.load_area("ocean-deep").to_dict()
    doc["grid"] = {**doc["grid"], "range_max_m": 40000.0}
    doc["propagation"] = {**doc.get("propagation", {}), "step_m": 25.0}
    doc["classes"] = [c for c in doc["classes"] if c["depth_m"] < 50.0]
    flat = acoustics.build_grid(_area(doc, "recip-flat"), workers=2)
    area = _area(doc, "recip-radial", radial=True)
    radials = area_radials(area)
    receivers = np.unique(np.concatenate([depth_axis_m(area, radials), [c.depth_m for c in area.classes],
                                          [SURFACE_ROW_M]]))
    r = flat["range"].values
    out = {}
    for label, mirrored, beams in variants:
        runs = image_runs(area, radials, receivers, mirrored, beams)
        k = k_rows(area, runs, run_all(runs)[0])[0]
        out[label] = {}
        for ic, cls in enumerate(area.classes):
            for ib, band in enumerate(area.bands):
                kf = flat["k_db"].values[ic, ib]
                ok = np.isfinite(kf) & (kf > -150.0) & (r > 2000.0)
                out[label][f"{cls.name} {band.name}"] = stats((k[ic, ib] - kf)[ok])
    return out


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
    runs = {label: image_runs(area, radials, receivers, mirrored, beams) for label, mirrored, beams in VARIANTS}
    cpu = {label: [] for label in runs}
    tables: dict[str, dict[int, np.ndarray]] = {}

    def once(label):
        tl, seconds = run_all(runs[label])
        cpu[label].append(seconds)
        tables[label] = tl  # BELLHOP is deterministic: every repeat gives the same

    session.interleave({label: (lambda label=label: once(label)) for label in runs}, args.repeats)
    out = {}
    before = statistics.median(cpu[VARIANTS[0][0]])
    for label, mirrored, beams in VARIANTS:
        seconds = statistics.median(cpu[label])
        row = {"mirrored": mirrored, "beams": beams, "runs": len(runs[label]), "bellhop_cpu_s": round(seconds, 2),
               "cpu_runs_s": [round(s, 2) for s in cpu[label]], "of_before": round(seconds / before, 3)}
        if beams < FINEST:
            finest = next(lab for lab, m, b in VARIANTS if m == mirrored and b == FINEST)
            row["against_finest"] = converged(np.stack([tables[label][j] for j, _ in runs[label]]),
                                              np.stack([tables[finest][j] for j, _ in runs[finest]]),
                                              area.propagation.tl_max_db)
        out[label] = row
    truth = truth_case(area, radials, {label: k_rows(area, runs[label], tables[label]) for label in COMPARED})
    reciprocity = reciprocity_case([v for v in VARIANTS if v[0] in COMPARED])
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
