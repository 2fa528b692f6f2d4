"""The surface's arrivals run: how its near-surface rows converge with the beams, and what a fan
dense only near the horizontal would buy, against the uniform fans, in one run.

``python -m bench.bench_image_fan [--repeats N] [--skip-reference]`` writes
``docs/results/image-fan.json``. On shelf-break's 12 radials, each radial's own arrivals run (the
build's .env, .bty and .ssp texts, reduced by ``acoustics.builder.surfaceimage.image_tl_db`` as
the build reduces it), with its beam fan changed:

- ``uniform N``: N beams over the fan's +-80 deg (the build takes 6000);
- ``split N / T / M``: within +-T deg of the horizontal the spacing of N beams over the fan,
  steeper the spacing of M; three BELLHOP runs (steep down, near the horizontal, steep up), each
  with its own spacing, so each one's beam amplitudes are right for its own spacing, and their
  arrivals joined per receiver before the reduction (so an arrival and its surface twin from
  different parts still pair).

Each variant's BELLHOP CPU (the processes' own, summed over the radials; median of the repeats)
and its near-surface rows (every class and band, every row within the surface's reach) against
the uniform fan of `REFERENCE_BEAMS`: |dTL| per cell (median, 90th percentile) and over 1 km of
range (the intensity averaged over ten 100 m cells, as the surface checks average KRAKEN's
coherent field), with the signed mean there (positive: lossier than the reference). And, unless
``--skip-reference``, the check in ``make test`` that does not share the beams' approximation (K
of ocean-deep's 6-8 m ships from the observer against their own runs: worst class and band
median, bound 0.5 dB) for the uniform fans of 6000 and `REFERENCE_BEAMS`.
"""

from __future__ import annotations

import argparse
import dataclasses
import resource
import statistics

import numpy as np

import envdata
from acoustics.bellhop.arrfile import Arrivals
from acoustics.bellhop.runner import run_env
from acoustics.builder.radial import depth_axis_m, plan_radial_image_runs
from acoustics.builder.surfaceimage import image_tl_db
from acoustics.surface import SURFACE_ROW_M
from bench.harness import Session
from envdata.radials import area_radials

#: The finest uniform fan, which the others are measured against.
REFERENCE_BEAMS = 12000
#: (label, beams over the whole fan near the horizontal, the dense part's half-angle in deg
#: (None: uniform), beams over the whole fan at the steep angles)
VARIANTS = (
    ("uniform 12000", 12000, None, None),
    ("uniform 6000 (the build)", 6000, None, None),
    ("uniform 3000", 3000, None, None),
    ("split 6000 / 20 / 3000", 6000, 20.0, 3000),
    ("split 6000 / 20 / 1500", 6000, 20.0, 1500),
    ("split 12000 / 20 / 1500", 12000, 20.0, 1500),
    ("split 12000 / 10 / 1500", 12000, 10.0, 1500),
)
#: Cells averaged for the 1 km figures (the grid's 100 m range step).
CELLS_PER_KM = 10


def fan_parts(n_dense: int, half_deg: float | None, n_steep: int | None, lo: float, hi: float
              ) -> list[tuple[int, float, float]]:
    """The runs' fans, (beams, first, last angle in deg): one uniform fan, or steep-down,
    near-horizontal and steep-up parts, each at its own spacing."""
    if half_deg is None:
        return [(n_dense, lo, hi)]
    dense = (hi - lo) / (n_dense - 1)
    steep = (hi - lo) / (n_steep - 1)
    n_mid = int(round(2.0 * half_deg / dense)) + 1
    n_side = int(round((hi - half_deg) / steep))
    return [(n_side, lo, -half_deg - steep), (n_mid, -half_deg, half_deg), (n_side, half_deg + steep, hi)]


def with_fan(env: str, beams: int, first: float, last: float, whole: tuple[int, float, float]) -> str:
    """The .env text with its fan line (``whole`` = the run's beams and angles) replaced."""
    old = f"\n{whole[0]}\n{whole[1]:g} {whole[2]:g} /\n"
    if env.count(old) != 1:
        raise RuntimeError(f"the run's fan {whole} is not in its .env text")
    return env.replace(old, f"\n{beams}\n{first:.10g} {last:.10g} /\n")


def joined(parts: list[Arrivals]) -> Arrivals:
    """One arrivals list per receiver from several runs' (same receivers), each receiver's in
    the runs' order."""
    if len(parts) == 1:
        return parts[0]
    order = np.argsort(np.concatenate([p.receiver_index for p in parts]), kind="stable")
    fields = ("amplitude", "phase_rad", "delay_s", "delay_imag_s", "receiver_angle_deg", "surface_bounces")
    return dataclasses.replace(parts[0], count=sum(p.count for p in parts),
                               **{f: np.concatenate([getattr(p, f) for p in parts])[order] for f in fields})


def child_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_variant(run, whole, parts) -> tuple[np.ndarray, float]:
    """The radial's near-surface TL (class, band, row, range) and BELLHOP's CPU seconds."""
    before = child_cpu()
    arrivals = [run_env(with_fan(run.env, *p, whole), files=dict(run.files), timeout_s=run.timeout_s).arrivals[0]
                for p in parts]
    seconds = child_cpu() - before
    return image_tl_db(joined(arrivals), run.image), seconds


def km_average(tl_db: np.ndarray) -> np.ndarray:
    """TL over 1 km of range: the intensity averaged over `CELLS_PER_KM` cells (the last axis)."""
    intensity = 10.0 ** (-np.asarray(tl_db, dtype=float) / 10.0)
    kernel = np.ones(CELLS_PER_KM) / CELLS_PER_KM
    mean = np.apply_along_axis(lambda x: np.convolve(x, kernel, mode="valid"), -1, intensity)
    return -10.0 * np.log10(np.maximum(mean, 1e-300))


def against(tl: np.ndarray, ref: np.ndarray, cap_db: float) -> dict:
    """Per cell and over 1 km: |dTL| median and p90, and the 1 km signed mean (dB)."""
    lit = (tl < cap_db) & (ref < cap_db)
    cell = np.abs(tl - ref)[lit]
    km, km_ref = km_average(tl), km_average(ref)
    lit_km = (km < cap_db) & (km_ref < cap_db)
    d = (km - km_ref)[lit_km]
    return {"cell_median_db": round(float(np.median(cell)), 3), "cell_p90_db": round(float(np.percentile(cell, 90)), 3),
            "km_median_db": round(float(np.median(np.abs(d))), 3),
            "km_p90_db": round(float(np.percentile(np.abs(d), 90)), 3), "km_mean_db": round(float(np.mean(d)), 3)}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--skip-reference", action="store_true")
    args = parser.parse_args(argv)
    session = Session("image-fan")
    area = envdata.load_area("shelf-break")
    prop = area.propagation
    radials = area_radials(area)
    depth = depth_axis_m(area, radials)
    receivers = np.unique(np.concatenate([depth, [c.depth_m for c in area.classes], [SURFACE_ROW_M]]))
    runs, _ = plan_radial_image_runs(area, radials, receivers)
    whole = (prop.image_beams, prop.angle_min_deg, prop.angle_max_deg)
    parts = {label: fan_parts(n, half, steep, prop.angle_min_deg, prop.angle_max_deg)
             for label, n, half, steep in VARIANTS}
    cpu = {label: [] for label in parts}
    tables: dict[str, np.ndarray] = {}

    def once(label):
        total, done = 0.0, []
        for run in runs:
            tl, seconds = run_variant(run, whole, parts[label])
            total += seconds
            done.append(tl)
        cpu[label].append(total)
        tables[label] = np.stack(done)  # BELLHOP is deterministic: every repeat gives the same

    session.interleave({label: (lambda label=label: once(label)) for label in parts}, args.repeats)
    reference = tables[VARIANTS[0][0]]
    build = VARIANTS[1][0]
    out = {}
    for label in parts:
        seconds = statistics.median(cpu[label])
        row = {"beams": [p[0] for p in parts[label]], "runs": len(parts[label]) * len(runs),
               "bellhop_cpu_s": round(seconds, 2), "cpu_runs_s": [round(s, 2) for s in cpu[label]]}
        if label != VARIANTS[0][0]:
            row.update(against(tables[label], reference, prop.tl_max_db))
        out[label] = row
    for label, row in out.items():
        row["of_build"] = round(row["bellhop_cpu_s"] / out[build]["bellhop_cpu_s"], 3)
        text = f"{row['bellhop_cpu_s']:.1f} s, {row['of_build']:.2f} of the build's"
        if "km_median_db" in row:
            text += (f"; against uniform {REFERENCE_BEAMS}: per cell {row['cell_median_db']} / {row['cell_p90_db']},"
                     f" over 1 km {row['km_median_db']} / {row['km_p90_db']} (mean {row['km_mean_db']:+})")
        session.say(label, text, "BELLHOP CPU; |dTL| median / p90, dB")
    check = {}
    if not args.skip_reference:
        from bench.crosscheck.surface import reciprocity_case

        for beams in (6000, REFERENCE_BEAMS):
            check[str(beams)] = max(s["median_db"] for s in reciprocity_case(image_beams=beams).values())
            session.say(f"K from the observer against the targets' own runs, uniform {beams}", check[str(beams)],
                        "dB, worst class and band median (bound 0.5)")
    session.write(repeats=args.repeats, area="shelf-break", radials=len(runs), rows=len(runs[0].image.receiver_depth_m),
                  reference_beams=REFERENCE_BEAMS, variants=out, reference_check_db=check, reference_bound_db=0.5)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
