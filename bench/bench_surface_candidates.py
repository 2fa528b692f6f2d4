"""The surface at a smaller price: each way of making a table from the observer for less, its
BELLHOP cost and how far it moves the tables, side by side with the build before it in one run.

``python -m bench.bench_surface_candidates [--repeats N] [--skip-reference]`` writes
``docs/results/surface-candidates.json``. On shelf-break's 12 radials (the build's own .env,
.bty and .ssp texts, run by ``bellhop.exe`` one at a time; CPU time of each process):

- ``per band`` (the build before this change): each radial's field runs at each band's centre,
  and its surface arrivals run of 6000 beams;
- ``one field run``: one field run per radial serves every band, each band's volume absorption
  put back by range (``acoustics.builder.bandruns.shared_run_hz``), and the same arrivals run;
- ``one field run, N arrivals beams``: the same with fewer beams in the arrivals run;
- ``incoherent, per band`` and ``incoherent, one field run``: the incoherent tables without the
  arrivals run, the price the surface is compared with.

Each candidate's band TL and K (the near-surface rows from its arrivals run) against the
``per band`` tables: |dTL| over the water's cells and |dK| over every class, band, radial and
range, median and 90th percentile. And the check the surface's tables answer to in ``make test``
(K of ocean-deep's 6-8 m ships from the observer against the targets' own runs, to 40 km, worst
class and band median, bound 0.5 dB: ``bench.crosscheck.surface.reciprocity_case``) for each
arrivals-beam count, unless ``--skip-reference``.
"""

from __future__ import annotations

import argparse
import dataclasses
import resource
import statistics

import numpy as np

import envdata
from acoustics.bellhop.runner import run_env
from acoustics.bellhop.shdfile import tl_from_pressure
from acoustics.builder.bandruns import band_tl_from_runs, freq_key
from acoustics.builder.imageruns import with_image_rows
from acoustics.builder.radial import bottom_on_grid_m, depth_axis_m, plan_radial_image_runs, plan_radial_runs
from acoustics.surface import SURFACE_ROW_M
from bench.harness import Session
from envdata.radials import area_radials

BEAMS = (6000, 4000, 3000)


def child_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run(run_) -> tuple[object, float]:
    """A run's result and its BELLHOP process's CPU time, s."""
    before = child_cpu()
    result = run_env(run_.env, files=dict(run_.files), timeout_s=run_.timeout_s)
    return result, child_cpu() - before


def plan(area, radials, receivers):
    """The runs of each candidate: (field runs, arrivals runs by beams)."""
    centres = [b.center_hz for b in area.bands]
    per_band, where_band = plan_radial_runs(area, radials, receivers, freqs_hz=centres)
    shared, where_shared = plan_radial_runs(area, radials, receivers)
    images = {}
    for beams in BEAMS:
        a = dataclasses.replace(area, propagation=dataclasses.replace(area.propagation, surface_image_beams=beams))
        runs, where = plan_radial_image_runs(a, radials, receivers)
        images[beams] = (runs, where)
    return {"per band": (per_band, where_band), "one field run": (shared, where_shared)}, images


def tables(area, fields, image, receivers, depth, bottom):
    """TL (class, band, radial, depth, range) and K's TL rows (class, band, radial, range)."""
    tl_max = area.propagation.tl_max_db
    field_runs, where = fields
    by_radial: dict[int, dict] = {}
    for r, result in field_runs:
        j, f = where[r.key]
        by_radial.setdefault(j, {})[freq_key(f)] = tl_from_pressure(result.field.pressure[0], tl_max)
    rows = {}
    if image is not None:
        runs, where_i = image
        for r, result in runs:
            from acoustics.builder.surfaceimage import image_tl_db

            j, idx = where_i[r.key]
            rows[j] = (idx, image_tl_db(result.arrivals[0], r.image))
    on_grid = np.searchsorted(receivers, depth)
    n_c, n_b, n_n = len(area.classes), len(area.bands), len(by_radial)
    tl = np.full((n_c, n_b, n_n, depth.size, area.grid.range_m().size), np.nan)
    k = np.full((n_c, n_b, n_n, area.grid.range_m().size), np.nan)
    for j, by_freq in by_radial.items():
        below = (depth[:, None] > bottom[j][None, :] + 1e-6) | ~np.isfinite(bottom[j])[None, :]
        for ic, cls in enumerate(area.classes):
            for ib, band in enumerate(area.bands):
                band_tl = band_tl_from_runs(area, cls, band, by_freq)
                if j in rows:
                    band_tl = with_image_rows(band_tl, rows[j][0], rows[j][1], ic, ib)
                tl[ic, ib, j] = np.where(below, np.nan, band_tl[on_grid])
                krow = band_tl[int(np.searchsorted(receivers, cls.depth_m))]
                k[ic, ib, j] = np.where(cls.depth_m < bottom[j], krow, np.nan)
    return tl, k


def moved(a: np.ndarray, b: np.ndarray) -> dict:
    ok = np.isfinite(a) & np.isfinite(b) & ((a < 150.0) | (b < 150.0))
    d = np.abs(a - b)[ok]
    return {"median_db": round(float(np.median(d)), 3), "p90_db": round(float(np.percentile(d, 90)), 3),
            "max_db": round(float(np.max(d)), 3)}


def reference_check(beams: int) -> float:
    """The make-test check's worst class and band median, dB (bound 0.5)."""
    from bench.crosscheck.surface import reciprocity_case

    return max(s["median_db"] for s in reciprocity_case(image_beams=beams).values())


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--skip-reference", action="store_true")
    args = parser.parse_args(argv)
    session = Session("surface-candidates")
    area = envdata.load_area("shelf-break")
    radials = area_radials(area)
    depth = depth_axis_m(area, radials)
    receivers = np.unique(np.concatenate([depth, [c.depth_m for c in area.classes], [SURFACE_ROW_M]]))
    bottom = np.stack([bottom_on_grid_m(area, rad) for rad in radials])
    fields, images = plan(area, radials, receivers)
    work = {**{f"field {name}": runs for name, (runs, _) in fields.items()},
            **{f"arrivals {beams}": runs for beams, (runs, _) in images.items()}}
    cpu = {name: [] for name in work}
    results = {}

    def once(name):
        total = 0.0
        done = []
        for r in work[name]:
            result, seconds = run(r)
            total += seconds
            done.append((r, result))
        cpu[name].append(total)
        results[name] = done

    session.interleave({name: (lambda name=name: once(name)) for name in work}, args.repeats)
    cost = {name: statistics.median(v) for name, v in cpu.items()}
    base = tables(area, (results["field per band"], fields["per band"][1]),
                  (results["arrivals 6000"], images[6000][1]), receivers, depth, bottom)
    candidates = {"per band (before)": ("per band", 6000),
                  "one field run": ("one field run", 6000),
                  **{f"one field run, {b} arrivals beams": ("one field run", b) for b in BEAMS[1:]},
                  "incoherent, per band": ("per band", None), "incoherent, one field run": ("one field run", None)}
    out = {}
    for label, (field, beams) in candidates.items():
        image = (results[f"arrivals {beams}"], images[beams][1]) if beams else None
        tl, k = tables(area, (results[f"field {field}"], fields[field][1]), image, receivers, depth, bottom)
        seconds = cost[f"field {field}"] + (cost[f"arrivals {beams}"] if beams else 0.0)
        row = {"bellhop_cpu_s": round(seconds, 2), "runs": len(work[f"field {field}"]) + (len(radials) if beams else 0)}
        if beams:
            row.update(tl_moved=moved(tl, base[0]), k_moved=moved(k, base[1]))
        out[label] = row
    before = out["per band (before)"]["bellhop_cpu_s"]
    for label, row in out.items():
        row["over_before"] = round(row["bellhop_cpu_s"] / before, 3)
        session.say(f"{label}: BELLHOP CPU", row["bellhop_cpu_s"], f"s ({row['over_before']:.2f} of before)")
        if "k_moved" in row:
            k_moved = row["k_moved"]
            session.say(f"{label}: K moved, median / p90", f"{k_moved['median_db']} / {k_moved['p90_db']}", "dB")
    for label, row in out.items():
        if "k_moved" in row:
            inc = "incoherent, one field run" if "one field" in label else "incoherent, per band"
            row["over_incoherent_same_runs"] = round(row["bellhop_cpu_s"] / out[inc]["bellhop_cpu_s"], 3)
            before_inc = out["incoherent, per band"]["bellhop_cpu_s"]
            row["over_incoherent_before"] = round(row["bellhop_cpu_s"] / before_inc, 3)
    reference = {}
    if not args.skip_reference:
        for beams in BEAMS:
            reference[str(beams)] = reference_check(beams)
            session.say(f"K from the observer against the targets' own runs, {beams} arrivals beams",
                        reference[str(beams)], "dB, worst class and band median (bound 0.5)")
    session.write(repeats=args.repeats, candidates=out, reference_check_db=reference,
                  reference_bound_db=0.5, area="shelf-break", radials=len(radials))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
