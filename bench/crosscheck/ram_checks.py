"""RAM against its two references: RAM 1.5's own test case and the Pekeris waveguide's mode sum.

``python -m bench.record docs/results/ram-checks.json -- python -m bench.crosscheck.ram_checks``

- RAM 1.5's test case (bench/crosscheck/ram_cases.py) against the Fortran RAM's TL line that
  pyram 1.3.0 ships (read from .venv-ref: ``make ramref``, RAM_REF_PYTHON): |dTL| at its 100
  ranges, mean and worst.
- The Pekeris waveguide (100 m of 1500 m/s water over a lossless 1800 m/s, 1.8 g/cm3
  half-space, source at 36 m) against its exact trapped-mode sum (bench/crosscheck/pekeris.py),
  receivers every 5 m from 5 to 95 m and every 10 m from 1 to 10 km, after a running intensity
  mean over 21 receivers (210 m) along range: |dTL| median and 90th percentile and the signed
  median, at 100 and 250 Hz, with RAM's default depth step (lambda/30) and with lambda/20.

tests/acoustics/ram/test_ram_reference.py and test_pekeris.py run the same cases
(`ram15_difference`, `pekeris_difference`) against their bounds.
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import numpy as np

from acoustics.ram import RamSettings, ram_tl_db
from bench.crosscheck import ram_cases as cases
from bench.crosscheck.pekeris import pekeris_tl_db

OUT = Path("docs/results/ram-checks.json")
PEKERIS_DEPTHS_M = np.arange(5.0, 100.0, 5.0)
PEKERIS_RANGES_M = np.arange(1000.0, 10_001.0, 10.0)
PEKERIS_WINDOW = 21  # receivers: 210 m
PEKERIS_FREQS_HZ = (100.0, 250.0)


def ram15_difference() -> np.ndarray:
    """|TL_RAM - TL_Fortran RAM| of RAM 1.5's test case at the reference line's 100 ranges, dB."""
    ref = np.loadtxt(cases.ram15_reference_path())
    if ref.shape != (100, 2):
        raise ValueError(f"tl_ref.line: expected 100 ranges of (range, TL), got shape {ref.shape}")
    env, settings = cases.ram15_case()
    tl = ram_tl_db(env, cases.RAM15_FREQ_HZ, [cases.RAM15_DEPTH_M], ref[:, 0], settings)[0]
    return np.abs(tl - ref[:, 1])


def pekeris_difference(freq_hz: float, depth_step_per_wavelength: float | None = None) -> np.ndarray:
    """TL_RAM - TL_modes on the Pekeris waveguide after the 210 m running mean, (depth, range), dB;
    RAM with its default settings, or with the depth step ``wavelength / depth_step_per_wavelength``."""
    env = cases.pekeris_environment()
    settings = RamSettings.for_environment(env, freq_hz)
    if depth_step_per_wavelength is not None:
        wavelength_m = cases.PEKERIS["c1_mps"] / freq_hz
        settings = dataclasses.replace(settings, depth_step_m=wavelength_m / depth_step_per_wavelength)
    tl = ram_tl_db(env, freq_hz, PEKERIS_DEPTHS_M, PEKERIS_RANGES_M, settings)
    exact = pekeris_tl_db(freq_hz, cases.PEKERIS_SOURCE_DEPTH_M, PEKERIS_DEPTHS_M, PEKERIS_RANGES_M, **cases.PEKERIS)
    return cases.range_average_tl_db(tl, PEKERIS_WINDOW) - cases.range_average_tl_db(exact, PEKERIS_WINDOW)


def _pekeris_stats(diff: np.ndarray, settings: RamSettings) -> dict:
    return {"median_db": round(float(np.median(np.abs(diff))), 3),
            "p90_db": round(float(np.percentile(np.abs(diff), 90)), 3),
            "signed_median_db": round(float(np.median(diff)), 3), "depth_step_m": settings.depth_step_m}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    ram15 = ram15_difference()
    pekeris = {}
    for f in PEKERIS_FREQS_HZ:
        default = RamSettings.for_environment(cases.pekeris_environment(), f)
        lam20 = dataclasses.replace(default, depth_step_m=cases.PEKERIS["c1_mps"] / f / 20.0)
        pekeris[f"{f:g}"] = {"default": _pekeris_stats(pekeris_difference(f), default),
                             "lambda_over_20": _pekeris_stats(pekeris_difference(f, 20.0), lam20)}
    doc = {"what": "RAM against RAM 1.5's Fortran TL line and the Pekeris waveguide's trapped-mode sum",
           "ram15": {"mean_abs_db": round(float(np.mean(ram15)), 5), "max_abs_db": round(float(np.max(ram15)), 4),
                     "ranges": int(ram15.size)},
           "pekeris": {"depths_m": [float(PEKERIS_DEPTHS_M[0]), float(PEKERIS_DEPTHS_M[-1]), 5.0],
                       "ranges_m": [float(PEKERIS_RANGES_M[0]), float(PEKERIS_RANGES_M[-1]), 10.0],
                       "window_receivers": PEKERIS_WINDOW, "by_freq_hz": pekeris}}
    cases.write_study_file(args.out, doc)
    print(f"RAM 1.5 mean {doc['ram15']['mean_abs_db']} dB, max {doc['ram15']['max_abs_db']} dB; Pekeris "
          + ", ".join(f"{f} Hz {v['default']['median_db']} / {v['default']['p90_db']} dB" for f, v in pekeris.items())
          + f"; wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
