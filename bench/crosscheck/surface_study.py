"""The sea-surface figures of docs/models.md: every case of ``bench.crosscheck.surface`` with the
default (semicoherent) tables and with incoherent beams, side by side.

``KRAKEN_PYTHON=.venv-kraken/bin/python python -m bench.crosscheck.surface_study
[--out docs/results/surface.json]`` (``make test`` makes .venv-kraken).
"""

from __future__ import annotations

import argparse
import contextlib
import time

import acoustics.surface
from bench.crosscheck import surface
from bench.harness import Session

THIRD_OCTAVE_100_HZ = (89.1, 112.2)


@contextlib.contextmanager
def reach_lifted():
    """The surface's reach set beyond any depth for the runs inside: the mirror at every source."""
    saved = acoustics.surface.REACH_WAVELENGTHS
    acoustics.surface.REACH_WAVELENGTHS = 1e6
    try:
        yield
    finally:
        acoustics.surface.REACH_WAVELENGTHS = saved


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--name", default="surface", help="result file docs/results/NAME.json")
    args = p.parse_args(argv)
    session = Session(args.name)
    cases = {}
    start = time.perf_counter()
    for mode in ("semicoherent", "incoherent"):
        cases[f"image flat 100-300 Hz, {mode}"] = surface.image_flat_case((100.0, 300.0), mode=mode)
        cases[f"munk flat TL beyond 5 km, 100 Hz tone, {mode}"] = surface.munk_flat_case((100.0, 100.0), mode=mode)
        cases[f"munk flat TL beyond 5 km, 89-112 Hz, {mode}"] = surface.munk_flat_case(THIRD_OCTAVE_100_HZ, mode=mode)
        cases[f"munk from the observer, 6 m to 100 m beyond 30 km, 89-112 Hz, {mode}"] = \
            surface.munk_radial_case(THIRD_OCTAVE_100_HZ, mode=mode)
        cases[f"munk from the observer, 6 m to 100 m beyond 30 km, 100 Hz tone, {mode}"] = \
            surface.munk_radial_case((100.0, 100.0), mode=mode)
        cases[f"shelf 5 m 250 Hz, 2-20 km, {mode}"] = surface.shelf_case(mode)
    # how deep the surface acts: sources at 4.5 and 6.5 wavelengths (the reach is 5), with the
    # mirror (the reach lifted for the measurement) and without (incoherent)
    for depth in (70.0, 100.0):
        for mode in ("semicoherent", "incoherent"):
            with reach_lifted():
                cases[f"munk flat TL beyond 5 km, 100 Hz tone, source at {depth:g} m, {mode}"] = \
                    surface.munk_flat_case((100.0, 100.0), mode=mode, target_m=depth)
    cases["image from the observer 100-300 Hz, semicoherent"] = surface.image_radial_case((100.0, 300.0))
    for mode in ("semicoherent", "incoherent"):
        cases[f"reciprocity ocean-deep K to 40 km, {mode}"] = surface.reciprocity_case(mode=mode)
    for name, s in cases.items():
        if "median_db" in s:
            session.say(name, s["median_db"], "dB median |d|")
    session.write(what="tmakit's tables for near-surface targets against the image-source solution, "
                       "KRAKEN's coherent field (1 km averages, trapped modes, the fan trapped) and the "
                       "target-centred runs (bench/crosscheck/surface.py)",
                  seconds=round(time.perf_counter() - start, 1), cases=cases)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
