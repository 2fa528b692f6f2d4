"""How many frequencies a band needs when its TL is the intensity average of coherent RAM runs.

``python -m bench.crosscheck.ram_band [--out docs/results/ram-band.json]``

The grids' band TL is the spectrum-weighted intensity average over log-spaced frequencies
across the band (``acoustics.kcurve.band_frequencies_hz``, ``band_weights``,
``band_average_tl_db``; the ocean-deep classes' f^-2 spectrum). A coherent run carries the
interference fringes of its one frequency; the average smooths them only when the frequencies
are close enough to sample the fringes' movement with frequency, which grows with range. For
n = 1, 3, 5, 7, 11, 15, 21 frequencies the band TL is compared with the band TL from 41
frequencies, point-wise over the receivers in the water: median and 90th percentile of |dTL|.

Cases: the Pekeris waveguide, band 100-300 Hz (FB1 of the built-in areas), 1-10 km; the
munk-1000 area (source at 100 m), band 50-150 Hz, 1-10 km. RAM's default settings.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

import envdata
from acoustics.kcurve import band_average_tl_db, band_frequencies_hz, band_weights
from acoustics.ram import RamSettings, ram_tl_db
from bench.crosscheck.ram_cases import munk_environment, pekeris_environment, write_study_file
from envdata.bands import Band

OUT = Path("docs/results/ram-band.json")
COUNTS = (1, 3, 5, 7, 11, 15, 21)
REFERENCE_COUNT = 41


def cases() -> list[dict]:
    ranges = np.arange(1000.0, 10_001.0, 50.0)
    return [
        {"name": "pekeris", "env": pekeris_environment(), "band": Band(name="FB1", low_hz=100.0, high_hz=300.0),
         "depth_m": np.arange(5.0, 100.0, 5.0), "range_m": ranges},
        {"name": "munk-1000", "env": munk_environment(), "band": Band(name="B50", low_hz=50.0, high_hz=150.0),
         "depth_m": np.arange(25.0, 1000.0, 25.0), "range_m": ranges},
    ]


def band_tl_db(case: dict, n: int, cls) -> np.ndarray:
    env = case["env"]
    freqs = band_frequencies_hz(case["band"], n)
    per_freq = np.stack([ram_tl_db(env, f, case["depth_m"], case["range_m"],
                                   RamSettings.for_environment(env, f))
                         for f in freqs])
    return band_average_tl_db(per_freq, band_weights(cls, freqs), 200.0)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    cls = envdata.load_area("ocean-deep").classes[0]  # f^-2, as every built-in class
    results = []
    for case in cases():
        t0 = time.perf_counter()
        ref = band_tl_db(case, REFERENCE_COUNT, cls)
        rows = []
        for n in COUNTS:
            d = np.abs(band_tl_db(case, n, cls) - ref)
            d = d[np.isfinite(d)]
            rows.append({"frequencies": n, "median_db": round(float(np.median(d)), 3),
                         "p90_db": round(float(np.percentile(d, 90)), 3)})
            print(f"{case['name']} {case['band'].name}: {n} frequencies: median {rows[-1]['median_db']} dB, "
                  f"p90 {rows[-1]['p90_db']} dB", flush=True)
        results.append({"case": case["name"], "band_hz": [case["band"].low_hz, case["band"].high_hz],
                        "seconds": round(time.perf_counter() - t0, 1), "against": REFERENCE_COUNT,
                        "counts": rows})
    doc = {"what": "band TL from n coherent RAM runs against 41, |dTL| point-wise over the receivers",
           "script": "python -m bench.crosscheck.ram_band", "class_spectrum": "f^-2",
           "ranges_m": [1000.0, 10000.0, 50.0], "results": results}
    write_study_file(args.out, doc)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
