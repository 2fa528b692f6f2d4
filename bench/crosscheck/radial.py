"""One shelf-break radial through tmakit's own BELLHOP input and through arlpy's create_env2d.

`compare_radial` runs both on the same bellhop.exe (arlpy in .venv-arlpy, see `run_arlpy`) and
returns the two TL fields and |dTL| over the receivers where both see sound;
``tests/acoustics/test_arlpy_radial.py`` asserts the agreement, and
``python -m bench.crosscheck.radial --out docs/results/arlpy-radial.json`` writes the figures the
docs quote (with ``ARLPY_PYTHON`` set, or .venv-arlpy in the repository).
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
from pathlib import Path

import numpy as np

import envdata
from acoustics.bellhop.envfile import RunSpec
from acoustics.bellhop.radialfiles import radial_files
from acoustics.bellhop.runner import run_env
from acoustics.bellhop.shdfile import tl_from_pressure
from bench.crosscheck.run_arlpy import arlpy_tl_db
from envdata.radials import area_radials

REPO = Path(__file__).resolve().parents[2]
BEARINGS_DEG = (180.0, 0.0)  # down the slope to the basin; up to the coast


def compare_radial(bearing: float, tmp_path: Path) -> dict:
    """Both TL fields of the shelf-break radial at ``bearing`` and their differences.

    Returns ``ours``, ``theirs`` (receiver depth x range, dB), ``wet`` (receivers above the
    bottom), ``heard`` (wet and TL < 120 dB in both) and ``abs_diff_db`` (|dTL| on ``heard``).
    """
    area = envdata.load_area("shelf-break")
    radial = next(r for r in area_radials(area) if r.bearing_deg == bearing)
    end = radial.land_range_m if radial.land_range_m is not None else area.grid.range_max_m
    rx_range = np.arange(500.0, min(end, area.grid.range_max_m) - 1.0, 500.0)
    ahead = radial.range_m >= 0.0
    deepest_ahead = float(radial.bottom_depth_m[ahead].max())  # arlpy: no receiver below it
    rx_depth = np.arange(10.0, min(deepest_ahead, 2000.0), 50.0)
    freq = 300.0
    beams = 2000
    obs = area.observer.depth_m

    spec = RunSpec(title="radial cross-check", freq_hz=freq, source_depth_m=(obs,),
                   receiver_depth_m=tuple(rx_depth), range_m=tuple(rx_range), n_beams=beams,
                   angle_min_deg=-80.0, angle_max_deg=80.0, absorption=envdata.Absorption.THORP)
    box_m = float(rx_range[-1]) * 1.01 + 10.0
    files = radial_files(area, radial, spec, step_m=25.0, box_range_m=box_m)
    ours = tl_from_pressure(run_env(files["env"], files={"bty": files["bty"], "ssp": files["ssp"]})
                            .field.pressure[0], 200.0)

    case = {
        "frequency_hz": freq, "source_depth_m": obs,
        "receiver_depth_m": rx_depth.tolist(), "receiver_range_m": rx_range.tolist(),
        "bathymetry": {"range_m": radial.range_m.tolist(),
                       "depth_m": radial.bottom_depth_m.tolist()},
        "ssp": {"depth_m": radial.ssp_depth_m.tolist(),
                "range_m": radial.ssp_range_m.tolist(),
                "speed_mps": radial.speed_mps.tolist()},
        "bottom": {"speed_mps": area.bottom.speed_mps, "density_gcc": area.bottom.density_gcc,
                   "attenuation_db_per_wavelength": area.bottom.attenuation_db_per_wavelength},
        "beams": {"count": beams, "min_angle_deg": -80.0, "max_angle_deg": 80.0},
        "mode": "incoherent", "tl_max_db": 200.0,
    }
    theirs = arlpy_tl_db(case, tmp_path)["tl_db"]
    bottom = np.interp(rx_range, radial.range_m, radial.bottom_depth_m)
    wet = rx_depth[:, None] < bottom[None, :]
    heard = wet & (ours < 120.0) & (theirs < 120.0)
    return {"ours": ours, "theirs": theirs, "wet": wet, "heard": heard,
            "abs_diff_db": np.abs(ours - theirs)[heard], "frequency_hz": freq, "beams": beams}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True, help="JSON file to write")
    args = parser.parse_args(argv)
    os.environ.setdefault("ARLPY_PYTHON", str(REPO / ".venv-arlpy" / "bin" / "python"))
    result = {"what": "shelf-break radials, tmakit's BELLHOP input against arlpy's create_env2d, "
                      "|dTL| where both TL < 120 dB", "radials": {}}
    for bearing in BEARINGS_DEG:
        with tempfile.TemporaryDirectory() as tmp:
            r = compare_radial(bearing, Path(tmp))
        d = r["abs_diff_db"]
        result["radials"][f"{bearing:g}"] = {
            "frequency_hz": r["frequency_hz"], "beams": r["beams"], "cells_heard": int(d.size),
            "cells_wet": int(r["wet"].sum()), "median_db": float(np.median(d)),
            "p90_db": float(np.percentile(d, 90)), "max_db": float(d.max())}
        print(f"bearing {bearing:g} deg: median {np.median(d):.2f} dB, p90 {np.percentile(d, 90):.2f} dB "
              f"over {d.size} receivers")
    out = Path(args.out)
    tmp = out.with_name(out.name + ".tmp")
    tmp.write_text(json.dumps(result, indent=1) + "\n")
    tmp.replace(out)


if __name__ == "__main__":
    main()
