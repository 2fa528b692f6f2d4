"""BELLHOP against KRAKEN's incoherent mode sum: the figures the KRAKEN cross-check test bounds.

``KRAKEN_PYTHON=.venv-kraken/bin/python python -m bench.crosscheck.kraken_study
[--out docs/results/kraken.json]`` (``make test`` makes .venv-kraken).
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path

import numpy as np

from bench.crosscheck.kraken import FLAT_CASE, MUNK_CASE, both_tl_db, windowed_tl_db


def figures(case, name: str, far_m: float) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        bellhop, kraken, info = both_tl_db(case, Path(tmp))
        seconds = time.perf_counter() - start
    rng = case[4]
    shadow = (bellhop >= 199.0) | (bellhop - kraken > 30.0)
    out = {"case": name, "freq_hz": case[1], "source_depth_m": case[2], "modes": info["modes"],
           "pelagic": info["pelagic"], "seconds_both": round(seconds, 2), "shadow_cells": int(shadow.sum()),
           "cells": int(shadow.size)}
    for lo in sorted({float(rng[0]), far_m}):
        d = (bellhop - kraken)[(rng >= lo)[None, :] & ~shadow]
        out[f"from_{lo / 1000:g}_km"] = {"median_db": round(float(np.median(np.abs(d))), 3),
                                         "p90_db": round(float(np.percentile(np.abs(d), 90)), 3),
                                         "signed_median_db": round(float(np.median(d)), 3)}
    band = windowed_tl_db(bellhop, 10).mean(axis=0) - windowed_tl_db(kraken, 10).mean(axis=0)
    out["depth_mean_10_range_windows_db"] = [round(float(x), 2) for x in band]
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=Path("docs/results/kraken.json"))
    args = p.parse_args(argv)
    doc = {"what": "BELLHOP (incoherent, tmakit's settings) against KRAKEN's incoherent mode sum "
                   "(pelagic, trapped modes), point-wise outside BELLHOP's shadows and over windows "
                   "of 10 ranges, depth-averaged",
           "script": "python -m bench.crosscheck.kraken_study",
           "results": [figures(FLAT_CASE, "flat 200 m", 2000.0), figures(MUNK_CASE, "munk 5000 m", 10000.0)]}
    args.out.write_text(json.dumps(doc, indent=1) + "\n")
    print(json.dumps(doc, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
