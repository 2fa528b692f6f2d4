"""BELLHOP transmission loss through arlpy (``arlpy.uwapm``), for the cross-check tests.

    .venv-arlpy/bin/python bench/crosscheck/arlpy_tl.py CASE.json OUT.json --bellhop EXE

Runs in the cross-check environment (arlpy 1.9.3 and its own numpy/scipy pins, no tmakit).
CASE.json describes one 2-D problem; every key but the optional ones is required:

    frequency_hz             one frequency, Hz
    source_depth_m           one source depth, m
    receiver_depth_m         list, m
    receiver_range_m         list, m
    water_depth_m            flat bottom, m; or instead
    bathymetry               {"range_m": [...], "depth_m": [...]}: range-dependent bottom
    ssp                      {"depth_m": [...], "speed_mps": [...]}: one profile; or
                             {"depth_m": [...], "range_m": [...], "speed_mps": [[...], ...]}
                             with speed_mps[i][j] at depth_m[i], range_m[j]: range-dependent
    ssp_interpolation        optional, "linear" (default: BELLHOP option C) or "spline"
    bottom                   {"speed_mps", "density_gcc", "attenuation_db_per_wavelength"}
    beams                    {"count", "min_angle_deg", "max_angle_deg"}; count 0 lets BELLHOP
                             choose
    mode                     optional, "incoherent" (default), "coherent" or "semicoherent"
    tl_max_db                optional, the cap for zero pressure, dB (default 200)

arlpy always asks BELLHOP for Thorp volume absorption and geometric hat beams. It runs
``bellhop.exe`` from PATH: EXE is put there under that name, so arlpy runs the given executable.
OUT.json gets ``tl_db`` (receiver depth x receiver range, TL = -20 lg |p|, dB), the receiver
axes, and the versions used. A failure (a bad case, arlpy refusing the environment, BELLHOP
failing) exits with status 2 and one ``error:`` paragraph on stderr, BELLHOP's own message
included; OUT.json is then not written.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
from importlib.metadata import version
from pathlib import Path

import arlpy.uwapm as pm
import numpy as np
import pandas as pd

REQUIRED = {"frequency_hz", "source_depth_m", "receiver_depth_m", "receiver_range_m", "ssp",
            "bottom", "beams"}
OPTIONAL = {"water_depth_m", "bathymetry", "ssp_interpolation", "mode", "tl_max_db"}


class CaseError(ValueError):
    pass


def _fields(table: dict, where: str, names: set[str]) -> dict:
    missing, unknown = names - table.keys(), table.keys() - names
    if missing or unknown:
        raise CaseError(f"{where}: missing {sorted(missing)}, unknown {sorted(unknown)}")
    return table


def env_kwargs(case: dict) -> dict:
    """The keyword arguments of ``arlpy.uwapm.create_env2d`` for ``case``, in arlpy's units."""
    keys = set(case)
    if REQUIRED - keys or keys - REQUIRED - OPTIONAL:
        raise CaseError(f"case: missing {sorted(REQUIRED - keys)}, "
                        f"unknown {sorted(keys - REQUIRED - OPTIONAL)}")
    if ("water_depth_m" in case) == ("bathymetry" in case):
        raise CaseError("case: give one of water_depth_m (flat) and bathymetry")
    if "bathymetry" in case:
        bty = _fields(case["bathymetry"], "bathymetry", {"range_m", "depth_m"})
        depth = np.column_stack([bty["range_m"], bty["depth_m"]])
    else:
        depth = float(case["water_depth_m"])
    ssp = case["ssp"]
    if "range_m" in ssp:
        ssp = _fields(ssp, "ssp", {"depth_m", "range_m", "speed_mps"})
        soundspeed = pd.DataFrame(np.asarray(ssp["speed_mps"], dtype=float),
                                  index=np.asarray(ssp["depth_m"], dtype=float),
                                  columns=np.asarray(ssp["range_m"], dtype=float))
    else:
        ssp = _fields(ssp, "ssp", {"depth_m", "speed_mps"})
        soundspeed = np.column_stack([ssp["depth_m"], ssp["speed_mps"]])
    interp = {"linear": pm.linear, "spline": pm.spline}
    name = case.get("ssp_interpolation", "linear")
    if name not in interp:
        raise CaseError(f"ssp_interpolation: {name!r} is not one of {sorted(interp)}")
    bottom = _fields(case["bottom"], "bottom",
                     {"speed_mps", "density_gcc", "attenuation_db_per_wavelength"})
    beams = _fields(case["beams"], "beams", {"count", "min_angle_deg", "max_angle_deg"})
    return dict(
        frequency=float(case["frequency_hz"]), tx_depth=float(case["source_depth_m"]),
        rx_depth=np.asarray(case["receiver_depth_m"], dtype=float),
        rx_range=np.asarray(case["receiver_range_m"], dtype=float),
        depth=depth, soundspeed=soundspeed, soundspeed_interp=interp[name],
        bottom_soundspeed=float(bottom["speed_mps"]),
        bottom_density=float(bottom["density_gcc"]) * 1000.0,  # arlpy takes kg/m^3
        bottom_absorption=float(bottom["attenuation_db_per_wavelength"]),
        nbeams=int(beams["count"]), min_angle=float(beams["min_angle_deg"]),
        max_angle=float(beams["max_angle_deg"]))


def transmission_loss(case: dict, bellhop: Path) -> dict:
    """Run ``case`` through arlpy and BELLHOP ``bellhop``; the contents of OUT.json."""
    modes = {"incoherent": pm.incoherent, "coherent": pm.coherent,
             "semicoherent": pm.semicoherent}
    mode = case.get("mode", "incoherent")
    if mode not in modes:
        raise CaseError(f"mode: {mode!r} is not one of {sorted(modes)}")
    tl_max_db = float(case.get("tl_max_db", 200.0))
    kwargs = env_kwargs(case)
    try:
        env = pm.create_env2d(**kwargs)
    except (AssertionError, KeyError, ValueError) as exc:
        raise CaseError(f"arlpy refuses the environment: {exc}") from None
    with tempfile.TemporaryDirectory(prefix="arlpy-tl-") as tmp:
        (Path(tmp) / "bellhop.exe").symlink_to(bellhop)
        os.environ["PATH"] = f"{tmp}{os.pathsep}{os.environ.get('PATH', '')}"
        base = str(Path(tmp) / "case")
        # with a file base of its own, arlpy keeps BELLHOP's files: the .prt says what failed
        pressure = pm.compute_transmission_loss(env, mode=modes[mode], fname_base=base)
        if pressure is None:
            prt = Path(base + ".prt")
            text = prt.read_text(errors="replace")[-3000:] if prt.exists() else "(no .prt file)"
            raise RuntimeError(f"arlpy's BELLHOP run failed ({bellhop}); BELLHOP's .prt ends:\n{text}")
    p = np.abs(np.asarray(pressure, dtype=complex))
    tl_db = -20.0 * np.log10(np.maximum(p, 10.0 ** (-tl_max_db / 20.0)))  # zero pressure: the cap
    return {"tl_db": tl_db.tolist(),
            "receiver_depth_m": np.asarray(pressure.index, dtype=float).tolist(),
            "receiver_range_m": np.asarray(pressure.columns, dtype=float).tolist(),
            "mode": mode, "tl_max_db": tl_max_db, "arlpy_version": version("arlpy"),
            "numpy_version": np.__version__, "bellhop_exe": str(bellhop)}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("case", type=Path, help="the problem, JSON (see above)")
    parser.add_argument("out", type=Path, help="where to write the TL, JSON")
    parser.add_argument("--bellhop", type=Path, required=True, help="the BELLHOP executable")
    args = parser.parse_args(argv)
    try:
        if not (args.bellhop.is_file() and os.access(args.bellhop, os.X_OK)):
            raise CaseError(f"--bellhop {args.bellhop}: not an executable file")
        case = json.loads(args.case.read_text())
        result = transmission_loss(case, args.bellhop.resolve())
    except (OSError, ValueError, RuntimeError) as exc:  # CaseError and bad JSON are ValueErrors
        print(f"error: {args.case}: {exc}", file=sys.stderr)
        return 2
    tmp = args.out.with_name(args.out.name + ".partial")
    tmp.write_text(json.dumps(result))
    tmp.replace(args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
