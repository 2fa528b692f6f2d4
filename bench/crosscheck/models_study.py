"""BELLHOP against RAM on the built-in areas and on narrow bands across frequency: agreement and cost.

``python -m bench.crosscheck.models_study [--out docs/results/models-areas.json]
[--crossover-out docs/results/ram-crossover.json] [--workers 2]``

Every grid is built by the real builder (``acoustics.build_grid``, ``--model bellhop`` and
``--model ram``) and compared through ``acoustics.grid.compare`` (the ``grids compare``
figures): median and 90th percentile of |dTL| over the cells both fill, of |dK| over the
ranges, and the rms and sd of dK (what the trackers' ``k_error_sd_db`` would have to hold if one
model were the truth and the other the table). Costs: the build's wall time, and the summed run
times of each model.

The built-in areas are cut to what RAM can do here in minutes (its cost grows as f^2 x depth x
range, and the machine is shared): the shelf-break FB1 on its radials at 0, 90, 180 and 270 deg
to 10 km (of 30), its FB2 on the 0 deg radial (upper slope toward the coast, 595 m) to 5 km, and
ocean-deep FB1 to 20 km (of 120: short of the first convergence zone near 60 km). Finished RAM
runs are kept in ``--cache`` (default .models-study-cache/), so an interrupted study resumes.
The crossover study takes the shelf-break radial at 0 deg to 10 km with half-octave bands
centred at 100, 200 and 400 Hz.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

import acoustics
import envdata
from acoustics.builder.bandruns import BuildStats
from acoustics.builder.modelchoice import AUTO_CROSSOVER_HZ, RAM_FREQS_PER_BAND
from acoustics.grid.compare import compare_grids


def _cut(name: str, *, range_max_m: float, bands: list[str] | None = None, bearings: list[float] | None = None,
         band_defs: list[dict] | None = None, tag: str) -> envdata.Area:
    area = envdata.load_area(name)
    doc = area.to_dict()
    doc["grid"] = {**doc["grid"], "range_max_m": range_max_m}
    if bands is not None:
        doc["bands"] = [b for b in doc["bands"] if b["name"] in bands]
    if band_defs is not None:
        doc["bands"] = band_defs
    if bearings is not None:
        doc["bearings"] = {"bearing_deg": bearings}
    doc["area"] = {**doc["area"], "name": f"{name}-{tag}"}
    path = envdata.area_path(name)
    return envdata.parse_area(doc, str(path), folder=path.parent)


def measure(area: envdata.Area, workers: int, cache: Path | None = None) -> dict:
    """Build ``area`` with BELLHOP and with RAM, compare, and time both."""
    out = {"area": area.name, "bands": [[b.name, b.low_hz, b.high_hz] for b in area.bands],
           "range_max_m": area.grid.range_max_m,
           "bellhop_mode": str(area.propagation.mode), "bellhop_beams": area.propagation.n_beams}
    grids = {}
    for model in ("bellhop", "ram"):
        stats = BuildStats()
        start = time.perf_counter()
        grid = acoustics.build_grid(area, model=model, workers=workers, stats=stats,
                                    cache_dir=None if cache is None else cache / area.name)
        grids[model] = acoustics.open_tables(grid, name=f"{area.name}-{model}")
        out[model] = {"wall_s": round(time.perf_counter() - start, 2), "runs": stats.runs_total,
                      "runs_reused": stats.runs_reused,
                      "run_seconds": round(stats.bellhop_seconds if model == "bellhop" else stats.ram_seconds, 2)}
        print(area.name, model, out[model], flush=True)
    comparison = compare_grids(grids["bellhop"], grids["ram"])
    rows = []
    k_b, k_r = grids["bellhop"].k_grid_db, grids["ram"].k_grid_db
    for row in comparison.rows:
        entry = {"class": row.cls_name, "band": row.band, "bearing_deg": row.bearing_deg,
                 "tl_median_db": round(row.tl_median_db, 3), "tl_p90_db": round(row.tl_p90_db, 3),
                 "tl_signed_median_db": round(row.tl_signed_median_db, 3),
                 "k_median_db": round(row.k_median_db, 3), "k_p90_db": round(row.k_p90_db, 3),
                 "tl_cells": row.tl_cells, "tl_one_sided": row.tl_one_sided}
        if row.bearing_deg is None:
            ic, ib = grids["bellhop"].class_index(row.cls_name), grids["bellhop"].band_index(row.band)
            dk = (k_r[ic, ib] - k_b[ic, ib]).ravel()
            dk = dk[np.isfinite(dk)]
            entry["k_rms_db"] = round(float(np.sqrt(np.mean(dk ** 2))), 3) if dk.size else None
            entry["k_sd_db"] = round(float(np.std(dk)), 3) if dk.size else None
        rows.append(entry)
    out["rows"] = rows
    return out


def crossover_cases() -> list[envdata.Area]:
    bands = [{"name": f"H{int(c)}", "low_hz": round(c / 2 ** 0.25, 2), "high_hz": round(c * 2 ** 0.25, 2)}
             for c in (100.0, 200.0, 400.0)]
    return [_cut("shelf-break", range_max_m=10000.0, band_defs=bands, bearings=[0.0], tag="crossover")]


def area_cases() -> list[envdata.Area]:
    return [_cut("shelf-break", range_max_m=10000.0, bands=["FB1"], bearings=[0.0, 90.0, 180.0, 270.0],
                 tag="fb1-4radials"),
            _cut("shelf-break", range_max_m=5000.0, bands=["FB2"], bearings=[0.0], tag="fb2-r0"),
            _cut("ocean-deep", range_max_m=20000.0, bands=["FB1"], tag="fb1-20km")]


def _write(path: Path, doc: dict) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(doc, indent=1) + "\n")
    tmp.replace(path)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=Path("docs/results/models-areas.json"))
    p.add_argument("--crossover-out", type=Path, default=Path("docs/results/ram-crossover.json"))
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--only", choices=["crossover", "areas"], help="one of the two studies")
    p.add_argument("--cache", type=Path, default=Path(".models-study-cache"),
                   help="finished runs, kept so that an interrupted study resumes")
    args = p.parse_args(argv)
    common = {"script": "python -m bench.crosscheck.models_study", "workers": args.workers,
              "ram_freqs_per_band": RAM_FREQS_PER_BAND,
              "comparison": "acoustics.grid.compare: B = RAM, A = BELLHOP; dTL over cells both fill "
                            "below the shadow cap, dK over ranges both have"}
    if args.only in (None, "crossover"):
        doc = {"what": "BELLHOP (the area's mode, bellhop_mode) against RAM (21 coherent runs per band) in "
                       "half-octave bands on the shelf-break radial at 0 deg to 10 km: agreement and cost per "
                       "frequency",
               "crossover_hz_in_use": AUTO_CROSSOVER_HZ, **common, "cases": []}
        for area in crossover_cases():
            doc["cases"].append(measure(area, args.workers))
            _write(args.crossover_out, doc)
    if args.only in (None, "areas"):
        doc = {"what": "BELLHOP against RAM on the built-in areas (cut to what RAM does here in minutes)",
               **common, "cases": []}
        for area in area_cases():
            doc["cases"].append(measure(area, args.workers, args.cache))
            _write(args.out, doc)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
