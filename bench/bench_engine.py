"""Another BELLHOP: pelagic's (a Rust port, GPL-3.0, in .venv-kraken) against ``bellhop.exe`` on
tmakit's own runs: time per run and the tables they make.

``python -m bench.bench_engine [--repeats N] [--radials I J ...]`` writes ``docs/results/engine.json``.
The runs are shelf-break's own (its build's .env, .bty and .ssp texts) on a few radials: each
radial's field run (1500 beams, TL, its receivers down to the radial's deepest bottom) and its
surface arrivals run (6000 beams, near-surface receivers). ``bellhop.exe`` runs each as the
build does (one process a run; wall and CPU time from the process's resource use); pelagic runs
them all in one process of .venv-kraken (``bench/crosscheck/pelagic_bellhop.py``: tmakit never
imports it), its time per run measured around its ``load(...).run()``. The two are interleaved, ``--repeats`` times.

Accuracy: the band TL each engine's runs make (the build's own reduction: the band average of
the class's spectrum for the field runs, ``acoustics.builder.surfaceimage`` for the arrivals'
near-surface rows), compared cell by cell (|dTL| median and 90th percentile, where either is
below 150 dB). Adopting another engine asks for it to be faster and within 0.1 dB median.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

import envdata
from acoustics.bellhop.arrfile import Arrivals, read_arr
from acoustics.bellhop.exe import find_bellhop
from acoustics.bellhop.shdfile import read_shd, tl_from_pressure
from acoustics.builder.bandruns import band_tl_from_runs
from acoustics.builder.radial import depth_axis_m, plan_radial_image_runs, plan_radial_runs
from acoustics.builder.surfaceimage import image_tl_db
from acoustics.surface import SURFACE_ROW_M
from bench.harness import REPO, Session
from envdata.radials import area_radials

SIDE = REPO / ".venv-kraken" / "bin" / "python"
SCRIPT = REPO / "bench" / "crosscheck" / "pelagic_bellhop.py"
#: Cells compared: where either engine's band TL is below this, dB (shadows are capped at 200).
TL_CUT_DB = 150.0


def sample_runs(area, radials: list[int]):
    """The build's runs of the radials asked for, each with its radial's index: the field run
    with the receivers down to the radial's deepest bottom (pelagic refuses a receiver below the
    water column; the build's deeper rows are NaN in the table), and the arrivals run."""
    all_radials = area_radials(area)
    depth = depth_axis_m(area, all_radials)
    receivers = np.unique(np.concatenate([depth, [c.depth_m for c in area.classes], [SURFACE_ROW_M]]))
    out = []
    for j in radials:
        radial = all_radials[j]
        wet = receivers[receivers <= float(np.max(radial.bottom_depth_m))]
        fields, _ = plan_radial_runs(area, [radial], wet)
        images, _ = plan_radial_image_runs(area, [radial], receivers)
        out += [(j, r) for r in fields + images]
    return out


def write_runs(folder: Path, runs) -> list[Path]:
    dirs = []
    for i, (_, run) in enumerate(runs):
        d = folder / f"r{i:03d}"
        d.mkdir()
        (d / "run.env").write_text(run.env)
        for suffix, text in run.files:
            (d / f"run.{suffix}").write_text(text)
        dirs.append(d)
    return dirs


def bellhop_exe(dirs: list[Path], exe: Path) -> list[tuple[float, float]]:
    """(wall, CPU) seconds of bellhop.exe on each run, one process at a time."""
    out = []
    for d in dirs:
        start = time.perf_counter()
        proc = subprocess.Popen([str(exe), "run"], cwd=d, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        _, status, usage = os.wait4(proc.pid, 0)
        if status != 0:
            raise SystemExit(f"bench: bellhop.exe failed in {d}")
        out.append((time.perf_counter() - start, usage.ru_utime + usage.ru_stime))
    return out


def pelagic_runs(folder: Path) -> dict:
    with tempfile.NamedTemporaryFile(suffix=".json") as out:
        subprocess.run([str(SIDE), str(SCRIPT), str(folder), out.name], check=True)
        return json.loads(Path(out.name).read_text())


def pelagic_arrivals(path: Path, run) -> Arrivals:
    """pelagic's arrivals (receivers range by range, depths fastest) in tmakit's order (depth-major)."""
    d = np.load(path)
    ranges, depths = np.unique(d["range_m"]), np.unique(d["depth_m"])
    nz, nr = depths.size, ranges.size
    k = np.arange(d["count"].size)
    ours = (k % nz) * nr + k // nz
    per_arrival = np.repeat(ours, d["count"].astype(np.int64))
    order = np.argsort(per_arrival, kind="stable")
    count = np.zeros(nz * nr, dtype=np.int64)
    count[ours] = d["count"]
    f64 = lambda name: np.asarray(d[name], dtype=float)[order]  # noqa: E731
    return Arrivals(freq_hz=run.freq_hz, source_depth_m=run.source_depth_m, receiver_depth_m=depths, range_m=ranges,
                    count=count.reshape(nz, nr), amplitude=f64("amplitude"), phase_rad=np.zeros(order.size),
                    delay_s=np.zeros(order.size), delay_imag_s=f64("delay_imag_s"),
                    receiver_angle_deg=f64("receiver_angle_deg"), surface_bounces=f64("surface_bounces"))


def band_tables(area, runs, dirs, engine: str) -> dict:
    """Per radial: the field runs' band TL (class, band, receiver, range) and the arrivals' rows."""
    tl_max = area.propagation.tl_max_db
    fields, images = {}, {}
    for (j, run), d in zip(runs, dirs):
        if run.image is not None:
            arr = read_arr(d / "run.arr")[0] if engine == "bellhop" else pelagic_arrivals(d / "pelagic.npz", run)
            images[j] = image_tl_db(arr, run.image)
        else:
            p = read_shd(d / "run.shd").pressure[0] if engine == "bellhop" else np.load(d / "pelagic.npz")["pressure"]
            fields.setdefault(j, {})[round(run.freq_hz, 6)] = tl_from_pressure(p, tl_max)
    out = {}
    for j, by_freq in fields.items():
        out[j] = (np.stack([np.stack([band_tl_from_runs(area, cls, band, by_freq) for band in area.bands])
                            for cls in area.classes]), images[j])
    return out


def stats(a: np.ndarray, b: np.ndarray) -> dict:
    ok = np.isfinite(a) & np.isfinite(b) & ((a < TL_CUT_DB) | (b < TL_CUT_DB))
    d = np.abs(a - b)[ok]
    return {"median_db": round(float(np.median(d)), 3), "p90_db": round(float(np.percentile(d, 90)), 3),
            "mean_signed_db": round(float(np.mean((a - b)[ok])), 3), "cells": int(d.size)}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--radials", type=int, nargs="+", default=[3, 6], help="radial indices of shelf-break")
    args = parser.parse_args(argv)
    if not SIDE.exists():
        raise SystemExit("bench: .venv-kraken is missing (make kraken installs pelagic there)")
    session = Session("engine")
    area = envdata.load_area("shelf-break")
    exe = find_bellhop().path
    runs = sample_runs(area, args.radials)
    kinds = ["arrivals" if run.image is not None else "field" for _, run in runs]
    with tempfile.TemporaryDirectory() as tmp:
        dirs = write_runs(Path(tmp), runs)
        exe_times, pel_times, versions = [], [], {}

        def pelagic():
            result = pelagic_runs(Path(tmp))
            versions["pelagic"] = result["pelagic"]
            pel_times.append([(result["runs"][d.name]["seconds"], result["runs"][d.name]["cpu_seconds"])
                              for d in dirs])

        session.interleave({"bellhop.exe": lambda: exe_times.append(bellhop_exe(dirs, exe)), "pelagic": pelagic},
                           args.repeats)
        ours, theirs = band_tables(area, runs, dirs, "bellhop"), band_tables(area, runs, dirs, "pelagic")
    per_kind = {}
    for kind in ("field", "arrivals"):
        idx = [i for i, k in enumerate(kinds) if k == kind]
        row = {"runs": len(idx)}
        for name, times in (("bellhop_exe", exe_times), ("pelagic", pel_times)):
            row[f"{name}_wall_s"] = round(statistics.median(sum(t[i][0] for i in idx) for t in times), 3)
            row[f"{name}_cpu_s"] = round(statistics.median(sum(t[i][1] for i in idx) for t in times), 3)
        row["pelagic_over_bellhop_exe_cpu"] = round(row["pelagic_cpu_s"] / row["bellhop_exe_cpu_s"], 3)
        row["pelagic_over_bellhop_exe_wall"] = round(row["pelagic_wall_s"] / row["bellhop_exe_wall_s"], 3)
        per_kind[kind] = row
        session.say(f"{kind} runs: pelagic / bellhop.exe CPU time", row["pelagic_over_bellhop_exe_cpu"], "x")
        session.say(f"{kind} runs: pelagic / bellhop.exe wall time", row["pelagic_over_bellhop_exe_wall"], "x")
    field = np.concatenate([ours[j][0].ravel() for j in ours]), np.concatenate([theirs[j][0].ravel() for j in theirs])
    rows = np.concatenate([ours[j][1].ravel() for j in ours]), np.concatenate([theirs[j][1].ravel() for j in theirs])
    accuracy = {"band TL of the field runs": stats(*field), "near-surface rows from the arrivals runs": stats(*rows)}
    for name, s in accuracy.items():
        session.say(f"{name}: |dTL| median", s["median_db"], "dB (adopt within 0.1)")
    session.write(repeats=args.repeats, radials=args.radials,
                  bearings_deg=[float(area.bearings.bearing_deg[j]) for j in args.radials], runs=per_kind,
                  accuracy=accuracy, extra_versions=versions,
                  licence="pelagic is GPL-3.0: run as its own process in .venv-kraken, never imported by tmakit")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
