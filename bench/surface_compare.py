"""How far the sea surface moved the built-in areas' tables: ``tmakit grids compare`` of each area
built with the settings before it (incoherent beams) and with
the default now (DESIGN.md "Near-surface sources and the beam fan", issue 25).

    python -m bench.surface_compare [--areas ...] [--before-checkout DIR]

Writes docs/results/surface-compare.json and, beside it, one ``grids compare --plot`` picture per
area (docs/results/surface-compare/AREA.png; B - A = now - before). The grids are built in
out/surface-compare/ (2 workers) with this checkout's code; each comparison is the command
``tmakit grids compare BEFORE NOW --json --plot PNG`` in a child process, its JSON kept whole.

- ocean-deep, shelf-break: the area file as it is now against the same with ``mode =
  "incoherent"`` (shelf-break's fan is 1500 beams before and after).
- munk-1000 keeps the paper's incoherent beams (its area file says so): its grid is the same
  before and after; the comparison is with the semicoherent mode instead, what the area would
  move if it took the default.
- shelf-break-atlas: one table (its first position and month, on the atlas's 50 m depth axis),
  built as a grid.

A bearing-dependent grid in the semicoherent mode has near-surface rows within its first depth
step (``acoustics.surface.with_surface_rows``) that the incoherent grid has not, and ``grids
compare`` compares only grids on one depth axis: the grid of now is compared on the rows of the
grid before (a copy without the added rows, ``NOW-rows-before.nc``); K is read at the class
depth either way, and its 0 m row (which now holds the loss 1 m down) is compared with the rest.

``--before-checkout DIR`` (a checkout of the commit before the surface landed) also builds
ocean-deep and shelf-break with that code and its defaults, and compares them with the
before-settings grids built here: the check that the "before" of this file is what the tables
were.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import subprocess
import sys
import time
from pathlib import Path

from bench.harness import REPO, RESULTS_DIR, Session, command_naming, portable

OUT = REPO / "out" / "surface-compare"
PLOTS = RESULTS_DIR / "surface-compare"
AREAS = ("ocean-deep", "munk-1000", "shelf-break", "shelf-break-atlas")


def _with(area, **changes):
    return dataclasses.replace(area, propagation=dataclasses.replace(area.propagation, **changes))


def pairs(names) -> dict:
    """area name -> (before, now, what the comparison is), as Areas."""
    import envdata
    from acoustics.builder.atlas import plan_atlas
    from envdata.atlasarea import table_area

    out = {}
    for name in names:
        if name == "shelf-break-atlas":
            atlas = envdata.load_area(name)
            plan = plan_atlas(atlas)
            now = table_area(atlas, plan.months[0], float(plan.lat_deg[0]), float(plan.lon_deg[0]))
            now = dataclasses.replace(now, grid=dataclasses.replace(now.grid, depth_step_m=atlas.atlas.depth_step_m))
            month = "the area's month" if plan.months[0] == 0 else f"month {plan.months[0]}"
            what = (f"one atlas table ({month}, {float(plan.lat_deg[0]):.4f} N "
                    f"{float(plan.lon_deg[0]):.4f} E, {atlas.atlas.depth_step_m:g} m depth axis): now against "
                    f"incoherent beams")
            out[name] = (_with(now, mode=envdata.TlMode.INCOHERENT), now, what)
            continue
        now = envdata.load_area(name)
        if now.propagation.mode is envdata.TlMode.INCOHERENT:  # munk-1000: the paper's mode, kept
            out[name] = (now, _with(now, mode=envdata.TlMode.SEMICOHERENT),
                         "the area keeps incoherent beams (before = now): its grid against the semicoherent mode")
        else:
            out[name] = (_with(now, mode=envdata.TlMode.INCOHERENT), now, "now (semicoherent) against incoherent beams")
    return out


def build(area, path: Path) -> dict:
    from acoustics.builder.gridfile import build_grid_file

    start = time.perf_counter()
    build_grid_file(area, path, workers=2, force=True)
    return {"file": str(path.relative_to(REPO)), "seconds": round(time.perf_counter() - start, 1),
            "mode": str(area.propagation.mode), "n_beams": area.propagation.n_beams}


def on_rows_of(grid_path: Path, other: Path) -> Path:
    """``grid_path`` without the depth rows ``other`` has not (the near-surface rows), written beside it."""
    import numpy as np
    import xarray as xr

    import acoustics

    with xr.open_dataset(other) as o:
        rows = o["depth"].values
    with xr.open_dataset(grid_path) as g:
        if g["depth"].size == rows.size and np.allclose(g["depth"].values, rows):
            return grid_path
        cut = g.sel(depth=rows).load()
    path = grid_path.with_name(grid_path.stem + "-rows-before.nc")
    acoustics.write_grid(cut, path)
    return path


def compare(a: Path, b: Path, plot: Path | None, cwd: Path = REPO) -> dict:
    args = [sys.executable, "-m", "tools.cli", "grids", "compare", str(a), str(b), "--json"]
    if plot is not None:
        args += ["--plot", str(plot), "--force"]
    done = subprocess.run(args, cwd=cwd, capture_output=True, text=True)
    if done.returncode != 0:
        raise SystemExit(f"surface_compare: {' '.join(args)} failed: {done.stderr}")
    data = json.loads(done.stdout.strip().splitlines()[-1])
    data["command"] = "tmakit " + " ".join(str(Path(x).relative_to(REPO)) if str(x).startswith(str(REPO)) else x
                                           for x in args[3:])
    return data


def summary(rows: list[dict]) -> dict:
    """Per class and band (all bearings): |dK| median / p90 and the signed median dTL."""
    return {f"{r['class']} {r['band']}": {"k_median_db": r["k_median_db"], "k_p90_db": r["k_p90_db"],
                                          "tl_median_db": r["tl_median_db"],
                                          "tl_signed_median_db": r["tl_signed_median_db"]}
            for r in rows if r["bearing_deg"] is None}


#: Range windows of the signed dK, km (the last one runs to the grid's end).
WINDOWS_KM = (0.0, 10.0, 20.0, 30.0, 50.0, 70.0, 1e9)


def _stats(d) -> dict | None:
    import numpy as np

    d = d[np.isfinite(d)]
    if not d.size:
        return None
    return {"median_db": round(float(np.median(d)), 3), "p10_db": round(float(np.percentile(d, 10)), 3),
            "p90_db": round(float(np.percentile(d, 90)), 3), "cells": int(d.size)}


def k_signed(before: Path, now: Path) -> tuple[dict, dict]:
    """dK = K_now - K_before per class and band (``grids compare`` gives |dK|; which way it
    moved is this): its median over every range (and bearing) both have, dB; and its median,
    10th and 90th percentiles by range window (``WINDOWS_KM``) and, for a bearing-dependent
    grid, by bearing and range window."""
    import numpy as np

    import acoustics

    a, b = acoustics.open_tables(before), acoustics.open_tables(now)
    r_km = np.asarray(a.range_m, dtype=float) / 1000.0
    bearings = np.asarray(getattr(a, "bearing_deg", []), dtype=float)
    whole, detail = {}, {}
    for ic, cls_name in enumerate(a.class_names):
        for ib, band in enumerate(a.band_names):
            d = np.asarray(b.k_grid_db[ic, ib], dtype=float) - np.asarray(a.k_grid_db[ic, ib], dtype=float)
            d = d.reshape(-1, r_km.size)  # (bearing or 1, range)
            whole[f"{cls_name} {band}"] = (_stats(d.ravel()) or {}).get("median_db")
            windows = {}
            for lo, hi in zip(WINDOWS_KM[:-1], WINDOWS_KM[1:]):
                cols = (r_km > lo) & (r_km <= hi)
                if not cols.any():
                    continue
                name = f"{lo:g}-{min(hi, r_km[-1]):g} km"
                entry = {"all": _stats(d[:, cols].ravel())}
                if bearings.size:
                    entry["by_bearing_deg"] = {f"{x:g}": _stats(d[j, cols]) for j, x in enumerate(bearings)}
                windows[name] = entry
            detail[f"{cls_name} {band}"] = windows
    return whole, detail


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--areas", nargs="*", default=list(AREAS))
    p.add_argument("--before-checkout", type=Path, help="a checkout of the code before the surface landed")
    args = p.parse_args(argv)
    # the checkout before is a machine path: the command names it BEFORE (its commit is in the file)
    named = {} if args.before_checkout is None else {str(args.before_checkout): "BEFORE"}
    session = Session("surface-compare", command=command_naming("bench.surface_compare", argv, named))
    OUT.mkdir(parents=True, exist_ok=True)
    PLOTS.mkdir(parents=True, exist_ok=True)
    areas = {}
    for name, (before, now, what) in pairs(args.areas).items():
        entry = {"what": what}
        paths = {}
        for label, area in (("before", before), ("now", now)):
            paths[label] = OUT / f"{name}-{label}.nc"
            entry[label] = build(area, paths[label])
            print(name, label, entry[label], flush=True)
        b_path = on_rows_of(paths["now"], paths["before"])
        entry["now_compared_on_rows_before"] = b_path != paths["now"]
        plot = PLOTS / f"{name}.png"
        result = compare(paths["before"], b_path, plot)
        entry["compare"] = result
        entry["plot"] = str(plot.relative_to(REPO))
        entry["by_class_band"] = summary(result["rows"])
        whole, detail = k_signed(paths["before"], b_path)
        for key, value in whole.items():
            entry["by_class_band"][key]["k_signed_median_db"] = value
        entry["k_signed_by_range"] = detail
        for key, s in entry["by_class_band"].items():
            session.say(f"{name} {key} |dK| median", s["k_median_db"], "dB")
        areas[name] = entry
    checks = {}
    if args.before_checkout is not None:
        code = args.before_checkout.resolve()
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=code, capture_output=True,
                                text=True).stdout.strip()
        for name in ("ocean-deep", "shelf-break"):
            if name not in areas:
                continue
            old = OUT / f"{name}-built-by-{commit}.nc"
            done = subprocess.run([sys.executable, "-m", "tools.cli", "grids", "build", name, "--out", str(old),
                                   "--workers", "2", "--force"], cwd=code, capture_output=True, text=True)
            if done.returncode != 0:
                raise SystemExit(f"surface_compare: the build at {code} failed: {done.stderr}")
            result = compare(REPO / areas[name]["before"]["file"], old, None)
            worst = max((r[k] or 0.0) for r in result["rows"] for k in ("tl_p90_db", "k_p90_db"))
            result = {**result, "a": portable(result["a"]), "b": portable(result["b"])}
            checks[name] = {"commit": commit, "worst_p90_db": worst, "compare": result}
            session.say(f"{name} before-settings grid against commit {commit}'s", worst, "dB (worst p90 |dTL|, |dK|)")
    session.write(what="grids compare of the built-in areas before the sea surface (incoherent beams) "
                       "and now (B - A = now - before)",
                  areas=areas, **({"before_code_check": checks} if checks else {}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
