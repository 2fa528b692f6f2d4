"""What each shortcut of the default grid build costs in K(r) accuracy, against the full computation.

Run with ``make bench`` (or ``python -m bench.bench_accuracy``). The full computation is every
quadrature frequency of every band at BELLHOP's automatic beam count, K(r) computed directly
(source at the class depth); against it: the default grid, the fixed fan of beams alone, the
one-run-per-band frequency shortcut alone, fans of 250 to 3000 beams, K by reciprocity (the
classes beyond the surface's reach), K of the near-surface classes from a table whose source is
the observer (``observer_tables``), and the whole TL field of one class and band. Prints
``name: value unit`` lines and writes docs/results/accuracy.json. The figures do not depend on
the machine's load; the run takes about twenty minutes on 2 cores (the full computation is the
naive loop of bench_grids.py).
"""

from __future__ import annotations

import dataclasses
import math
import os
import time

import numpy as np

import acoustics
import envdata
from acoustics.builder.plan import near_surface
from bench.harness import Session

session = Session("accuracy")


def k_difference(a, b) -> tuple[float, float, float]:
    d = np.abs(np.asarray(a) - np.asarray(b)).ravel()
    return float(np.median(d)), float(np.percentile(d, 95)), float(np.sqrt(np.mean(d ** 2)))


def main() -> None:
    area = envdata.load_area(envdata.DEFAULT_AREA)
    ncores = os.cpu_count() or 1
    grid = acoustics.build_grid(area, workers=ncores)  # the default settings, as `grids build` makes it

    # -- what each shortcut costs in K(r) accuracy, against the full computation ---------------
    prop = area.propagation
    full = dataclasses.replace(area, propagation=dataclasses.replace(prop, n_beams=0, frequency_shortcut=False))
    beams_only = dataclasses.replace(area, propagation=dataclasses.replace(prop, frequency_shortcut=False))
    shortcut_only = dataclasses.replace(area, propagation=dataclasses.replace(prop, n_beams=0))
    k_full = acoustics.build_k(full, reciprocity_min_depth_m=math.inf, workers=ncores)
    k_beams = acoustics.build_k(beams_only, reciprocity_min_depth_m=math.inf, workers=ncores)
    k_short = acoustics.build_k(shortcut_only, reciprocity_min_depth_m=math.inf, workers=ncores)
    k_recip = acoustics.build_k(area, reciprocity_min_depth_m=0.0, workers=ncores)
    for name, k in (("default_grid", grid["k_db"]), ("fixed_beam_fan", k_beams),
                    ("frequency_shortcut", k_short)):
        med, p95, rms = k_difference(k, k_full)
        session.say(f"k_error_{name}_vs_full_median", med, "dB")
        session.say(f"k_error_{name}_vs_full_p95", p95, "dB")
    # how many beams incoherent K(r) needs (one run per band; reference: BELLHOP's own count)
    for n_beams in (250, 500, 1000, 1500, 3000):
        fan = dataclasses.replace(area, propagation=dataclasses.replace(prop, n_beams=n_beams))
        start = time.perf_counter()
        k_fan = acoustics.build_k(fan, reciprocity_min_depth_m=math.inf, workers=ncores)
        seconds = time.perf_counter() - start
        med, p95, _ = k_difference(k_fan, k_full)
        session.say(f"k_error_{n_beams}_beams_vs_full_median", med, "dB")
        session.say(f"k_error_{n_beams}_beams_vs_full_p95", p95, f"dB ({seconds:.1f} s for K alone)")
    # the whole TL field of one class and band against the full computation
    nps, fb1 = area.classes[0], area.bands[0]
    one = dict(classes=(nps,), bands=(fb1,))
    tl_default = grid["tl_db"].sel({"class": nps.name, "band": fb1.name}).values
    tl_full = acoustics.build_grid(dataclasses.replace(full, **one), workers=ncores)["tl_db"].values[0, 0]
    audible = tl_full < 120.0  # leave out deep shadows, where no band would be detected
    d = np.abs(tl_default - tl_full)[audible]
    session.say(f"tl_field_error_default_vs_full_{nps.name}_{fb1.name}_median", float(np.median(d)), "dB")
    session.say(f"tl_field_error_default_vs_full_{nps.name}_{fb1.name}_p95", float(np.percentile(d, 95)), "dB")
    for cls in area.classes:
        if near_surface(area, cls):  # build_k runs it directly whatever it is asked: see below
            continue
        med, p95, _ = k_difference(k_recip.sel({"class": cls.name}), grid["k_db"].sel({"class": cls.name}))
        session.say(f"k_error_reciprocity_{cls.name}_{cls.depth_m:g}m_median", med, "dB")
        session.say(f"k_error_reciprocity_{cls.name}_{cls.depth_m:g}m_p95", p95, "dB")
    observer_tables(area, ncores)


def observer_tables(area, workers: int) -> None:
    """K of the near-surface classes from a table whose source is the observer, against the same
    from the targets' own runs (the flat grid's K), in each mode.

    ``build_k`` never takes a class within the surface's reach by reciprocity (its K from the
    target's own runs carries the surface at the target), so its reciprocity figure for them
    would compare the direct runs with themselves. The tables from the observer are the
    bearing-dependent grids and atlases: here one radial of the area (an origin and one
    bearing over the same flat sea), whose near-surface rows come from the arrivals run with
    each arrival's surface image at the target (incoherent beams: the beams alone). Both sides
    run at the radial builder's ray step, so that only the end the source is at differs.
    """
    from acoustics.builder.radial import DEFAULT_STEP_M

    doc = area.to_dict()
    doc["propagation"] = {**doc.get("propagation", {}), "step_m": DEFAULT_STEP_M}
    doc["classes"] = [c for c, cls in zip(doc["classes"], area.classes) if near_surface(area, cls)]
    for mode in ("semicoherent", "incoherent"):
        doc["propagation"]["mode"] = mode
        flat = envdata.parse_area({**doc, "area": {**doc["area"], "name": f"{area.name}-flat"}}, "accuracy-flat")
        radial = envdata.parse_area({**doc, "area": {**doc["area"], "name": f"{area.name}-radial"},
                                     "origin": {"lat_deg": area.latitude_deg, "lon_deg": area.longitude_deg},
                                     "bearings": {"bearing_deg": [0.0]}}, "accuracy-radial")
        k_direct = acoustics.build_k(flat, reciprocity_min_depth_m=math.inf, workers=workers)
        k_table = acoustics.build_grid(radial, workers=workers)["k_db"].isel(bearing=0)
        for cls in flat.classes:
            a, b = k_table.sel({"class": cls.name}).values, k_direct.sel({"class": cls.name}).values
            ok = np.isfinite(a) & np.isfinite(b)
            med, p95, _ = k_difference(a[ok], b[ok])
            key = f"k_error_observer_table_{mode}_{cls.name}_{cls.depth_m:g}m"
            session.say(f"{key}_median", med, "dB")
            session.say(f"{key}_p95", p95, "dB")
            session.say(f"{key}_mean", float(np.mean(a[ok] - b[ok])), "dB (table - direct)")


if __name__ == "__main__":
    main()
    session.write()
