"""The ASA wedge benchmark: BELLHOP against RAM at the 30 m receiver.

``python -m bench.crosscheck.ram_wedge [--out docs/results/ram-wedge.json]``

Jensen & Ferla (1990): 25 Hz, source at 100 m, the bottom from 200 m at the source to the
shore at 4 km, 1500 m/s water over 1700 m/s, 1.5 g/cm3, 0.5 dB/wavelength (bench/crosscheck/
ram_cases.py). Both models take it the way the bearing-dependent grid does: BELLHOP through
``acoustics.bellhop.radialfiles.radial_files`` (range-dependent .bty, 'Q' .ssp) and
``acoustics.bellhop.runner.run_env``, RAM through ``RamEnvironment.from_radial`` with its
default settings. BELLHOP runs coherent with the grids' geometric hat beams ('G'), 2000 beams
over -89..89 deg, a 5 m ray step: coherent against coherent, since the wedge's point is the
modal interference and cut-off RAM computes. Compared at 30 m every 10 m from 100 m to 3.4 km
(where the bottom passes 30 m), after a running intensity mean over 21 receivers (210 m,
3.5 wavelengths) along range.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from acoustics.bellhop.envfile import RunSpec
from acoustics.bellhop.radialfiles import radial_files
from acoustics.bellhop.runner import run_env
from acoustics.bellhop.shdfile import tl_from_pressure
from acoustics.ram import RamSettings, ram_tl_db
from bench.crosscheck.ram_cases import (
    WEDGE_FREQ_HZ,
    WEDGE_RECEIVER_DEPTH_M,
    WEDGE_SHORE_M,
    WEDGE_SOURCE_DEPTH_M,
    range_average_tl_db,
    wedge_area,
    wedge_environment,
    wedge_radial,
    write_study_file,
)
from envdata.area import Absorption, TlMode

OUT = Path("docs/results/ram-wedge.json")
RANGES_M = np.arange(100.0, 3401.0, 10.0)
WINDOW = 21
STEP_M = 5.0
N_BEAMS = 2000


def compare_wedge() -> dict:
    """TL of both models at the receiver and the statistics of their range-averaged difference."""
    area, radial = wedge_area(), wedge_radial()
    spec = RunSpec(title="ASA wedge", freq_hz=WEDGE_FREQ_HZ, source_depth_m=(WEDGE_SOURCE_DEPTH_M,),
                   receiver_depth_m=(WEDGE_RECEIVER_DEPTH_M,), range_m=tuple(RANGES_M), mode=TlMode.COHERENT,
                   beam_type="G", n_beams=N_BEAMS, angle_min_deg=-89.0, angle_max_deg=89.0,
                   absorption=Absorption.NONE)
    files = radial_files(area, radial, spec, step_m=STEP_M, box_range_m=WEDGE_SHORE_M + 100.0)
    t0 = time.perf_counter()
    run = run_env(files["env"], files={"bty": files["bty"], "ssp": files["ssp"]})
    bellhop_s = time.perf_counter() - t0
    bellhop = tl_from_pressure(run.field.pressure[0], 200.0)[0]
    env = wedge_environment()
    settings = RamSettings.for_environment(env, WEDGE_FREQ_HZ)
    t0 = time.perf_counter()
    ram = ram_tl_db(env, WEDGE_FREQ_HZ, [WEDGE_RECEIVER_DEPTH_M], RANGES_M, settings)[0]
    ram_s = time.perf_counter() - t0
    diff = np.abs(range_average_tl_db(ram[None], WINDOW)[0] - range_average_tl_db(bellhop[None], WINDOW)[0])
    point = np.abs(ram - bellhop)
    return {"range_m": RANGES_M, "bellhop_tl_db": bellhop, "ram_tl_db": ram, "abs_diff_db": diff,
            "median_db": float(np.median(diff)), "p90_db": float(np.percentile(diff, 90)),
            "point_median_db": float(np.median(point)), "point_p90_db": float(np.percentile(point, 90)),
            "bellhop_s": bellhop_s, "ram_s": ram_s}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    r = compare_wedge()
    doc = {"what": "ASA wedge, 25 Hz, receiver 30 m: |TL_RAM - TL_BELLHOP| after a 210 m running intensity mean",
           "script": "python -m bench.crosscheck.ram_wedge",
           "bellhop": f"coherent, geometric hat beams, {N_BEAMS} beams over -89..89 deg, ray step {STEP_M:g} m",
           "ram": "RamSettings.for_environment defaults",
           "ranges_m": [float(RANGES_M[0]), float(RANGES_M[-1]), 10.0], "window_receivers": WINDOW,
           "median_db": round(r["median_db"], 3), "p90_db": round(r["p90_db"], 3),
           "point_median_db": round(r["point_median_db"], 3), "point_p90_db": round(r["point_p90_db"], 3),
           "bellhop_s": round(r["bellhop_s"], 3), "ram_s": round(r["ram_s"], 3),
           "tl_every_500m": {"range_m": RANGES_M[::50].tolist(),
                             "bellhop_db": np.round(r["bellhop_tl_db"][::50], 2).tolist(),
                             "ram_db": np.round(r["ram_tl_db"][::50], 2).tolist()}}
    write_study_file(args.out, doc)
    print(f"median {doc['median_db']} dB, p90 {doc['p90_db']} dB (point-wise {doc['point_median_db']} / "
          f"{doc['point_p90_db']} dB); wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
