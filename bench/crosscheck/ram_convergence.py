"""RAM convergence study: how fine dz, dr, the Pade terms and the absorbing layer must be.

``python -m bench.crosscheck.ram_convergence [--out docs/results/ram-convergence.json]``

For each case (bench/crosscheck/ram_cases.py: the Pekeris waveguide, the ASA wedge, the deep
munk-1000 area) and frequency, a reference run (dz = lambda/80, dr = lambda/8, 8 Pade terms, a
40-lambda absorbing layer; lambda = 1500 m/s / f) and one run per candidate, each changing one
setting from the candidate rule. Receivers: the case's depths, ranges every 4 lambda (so
every candidate dr up to 4 lambda lands exactly on them). Measured per candidate: median and
90th percentile of |TL - TL_ref| point-wise, and after a running intensity mean over 5
receivers along range (20 lambda), over every receiver in the water; and the run's time.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from acoustics.ram import RamSettings, ram_tl_db
from bench.crosscheck.ram_cases import (
    munk_environment,
    pekeris_environment,
    range_average_tl_db,
    wedge_environment,
    write_study_file,
)

OUT = Path("docs/results/ram-convergence.json")
REFERENCE = {"dz_wavelengths": 1 / 80, "dr_wavelengths": 1 / 8, "pade_terms": 8, "layer_wavelengths": 40.0}
RULE = {"dz_wavelengths": 1 / 30, "dr_wavelengths": 1 / 2, "pade_terms": 8, "layer_wavelengths": 20.0}
#: One setting at a time away from the rule.
CANDIDATES = ([("dz_wavelengths", v) for v in (1 / 10, 1 / 20, 1 / 30, 1 / 40)]
              + [("dr_wavelengths", v) for v in (1 / 4, 1 / 2, 1.0, 2.0, 4.0)]
              + [("pade_terms", v) for v in (2, 4, 6)]
              + [("layer_wavelengths", v) for v in (10.0,)])
WINDOW = 5  # receivers: 20 wavelengths


def cases() -> list[dict]:
    return [
        {"name": "pekeris", "env": pekeris_environment(), "freqs_hz": (50.0, 100.0, 200.0, 400.0),
         "depth_m": np.arange(5.0, 100.0, 5.0), "range_max_m": 10_000.0},
        {"name": "wedge", "env": wedge_environment(), "freqs_hz": (25.0, 50.0, 100.0),
         "depth_m": np.arange(5.0, 200.0, 5.0), "range_max_m": 4_000.0},
        {"name": "munk-1000", "env": munk_environment(), "freqs_hz": (50.0, 100.0, 200.0),
         "depth_m": np.arange(25.0, 1000.0, 25.0), "range_max_m": 20_000.0},
    ]


def settings_for(freq_hz: float, env, p: dict) -> RamSettings:
    lam = 1500.0 / freq_hz
    layer = p["layer_wavelengths"] * lam
    return RamSettings(range_step_m=p["dr_wavelengths"] * lam, depth_step_m=p["dz_wavelengths"] * lam,
                       grid_depth_m=env.max_bottom_depth_m + layer, absorbing_layer_m=layer,
                       pade_terms=int(p["pade_terms"]))


def differences(tl: np.ndarray, ref: np.ndarray) -> dict:
    out = {}
    for label, a, b in (("point", tl, ref),
                        ("averaged", range_average_tl_db(tl, WINDOW), range_average_tl_db(ref, WINDOW))):
        d = np.abs(a - b)[np.isfinite(a) & np.isfinite(b)]
        out[f"{label}_median_db"] = round(float(np.median(d)), 3)
        out[f"{label}_p90_db"] = round(float(np.percentile(d, 90)), 3)
    return out


def run_case(case: dict, freq_hz: float) -> dict:
    env = case["env"]
    lam = 1500.0 / freq_hz
    step = 4.0 * lam
    rng = step * np.arange(1, int(case["range_max_m"] // step) + 1)
    rng = rng[rng >= 500.0]
    t0 = time.perf_counter()
    ref = ram_tl_db(env, freq_hz, case["depth_m"], rng, settings_for(freq_hz, env, REFERENCE))
    t_ref = time.perf_counter() - t0
    rows = []
    for key, value in CANDIDATES:
        p = dict(RULE, **{key: value})
        t0 = time.perf_counter()
        tl = ram_tl_db(env, freq_hz, case["depth_m"], rng, settings_for(freq_hz, env, p))
        rows.append({"changed": key, "value": value, "seconds": round(time.perf_counter() - t0, 3),
                     **differences(tl, ref)})
    return {"case": case["name"], "freq_hz": freq_hz, "reference_seconds": round(t_ref, 2),
            "ranges_m": [float(rng[0]), float(rng[-1]), float(step)], "candidates": rows}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    results = []
    for case in cases():
        for f in case["freqs_hz"]:
            res = run_case(case, f)
            results.append(res)
            rule = next(c for c in res["candidates"] if c["changed"] == "dz_wavelengths"
                        and abs(c["value"] - RULE["dz_wavelengths"]) < 1e-12)
            print(f"{case['name']} {f:g} Hz: rule point median {rule['point_median_db']} dB, p90 "
                  f"{rule['point_p90_db']} dB; averaged median {rule['averaged_median_db']} dB "
                  f"(reference {res['reference_seconds']} s)", flush=True)
    doc = {"what": "RAM (easypyram) convergence: |TL - TL_ref| over receivers in the water",
           "script": "python -m bench.crosscheck.ram_convergence",
           "reference": REFERENCE, "rule": RULE, "window_receivers": WINDOW,
           "wavelength": "1500 m/s / f", "receivers": "ranges every 4 wavelengths from 500 m",
           "results": results}
    write_study_file(args.out, doc)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
