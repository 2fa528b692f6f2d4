"""KRAKEN (pelagic, in .venv-kraken) for a flat area: its input written here, run as its own process.

``make test`` makes .venv-kraken and gives its interpreter in ``KRAKEN_PYTHON``; tmakit's own
environment does not hold pelagic. The KRAKEN input is the Acoustics Toolbox's .env (normal
modes: the area's profile, c-linear, vacuum surface, attenuation in dB/wavelength, the area's
half-space) and FIELD's .flp (point source, adiabatic, incoherent mode addition, or coherent).
Only trapped modes are kept (phase speeds below the bottom's): at the ranges compared (>= 2 km
here) the leaky ones have decayed by tens of dB.
"""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np

import envdata
from acoustics.bellhop.envfile import env_text, fmt_list, fmt_number
from acoustics.bellhop.runner import run_env
from acoustics.bellhop.shdfile import tl_from_pressure
from acoustics.builder.plan import run_spec
from bench.crosscheck.sidevenv import CrosscheckError, side_python
from envdata.area import Area

SCRIPT = Path(__file__).with_name("kraken_tl.py")


def kraken_python() -> str:
    """The KRAKEN environment's interpreter; a failure (not a skip) when there is none."""
    return side_python("KRAKEN_PYTHON", ".venv-kraken", "pelagic")


def kraken_case(area: Area, freq_hz: float, source_depth_m: float, depth_m, range_m, *,
                incoherent: bool = True) -> dict:
    """KRAKEN's .env and FIELD's .flp texts for a flat ``area`` (one profile, half-space bottom)."""
    ssp = area.water.ssp
    bottom = area.bottom
    depth_max = float(area.water.depth_m)
    env = [f"'tmakit KRAKEN cross-check {area.name}'", fmt_number(freq_hz), "1",
           f"'{ssp.interpolation}VW'",  # the profile's interpolation, vacuum top, dB/wavelength
           f"0 0.0 {fmt_number(depth_max)}"]
    env += [f"{fmt_number(z)} {fmt_number(c)} 0.0 1.0 0.0 0.0 /" for z, c in zip(ssp.depth_m, ssp.speed_mps)]
    env += ["'A' 0.0",
            f"{fmt_number(depth_max)} {fmt_number(bottom.speed_mps)} 0.0 {fmt_number(bottom.density_gcc)} "
            f"{fmt_number(bottom.attenuation_db_per_wavelength)} 0.0 /",
            f"0.0 {fmt_number(bottom.speed_mps)}",  # trapped modes only
            fmt_number(float(np.max(range_m)) / 1000.0 * 1.01),  # km
            "1", f"{fmt_number(source_depth_m)} /", str(len(depth_m)), fmt_list(depth_m)]
    r_km = np.asarray(range_m, dtype=float) / 1000.0
    flp = ["/", "'RA I'" if incoherent else "'RA C'", "9999", "1", "0.0 /", str(r_km.size),
           f"{fmt_number(r_km[0])} {fmt_number(r_km[-1])} /", "1", f"{fmt_number(source_depth_m)} /",
           str(len(depth_m)), fmt_list(depth_m), str(len(depth_m)), fmt_list(np.zeros(len(depth_m)))]
    return {"env": "\n".join(env) + "\n", "flp": "\n".join(flp) + "\n"}


def kraken_tl_db(case: dict, tmp_path: Path, *, timeout_s: float = 300.0) -> dict:
    """Run `kraken_tl.py` on ``case`` in .venv-kraken; its output with ``tl_db`` (depth x range)
    and the receiver axes as arrays. A failure of the script raises `CrosscheckError` with its message."""
    case_path, out_path = tmp_path / "kraken-case.json", tmp_path / "kraken-tl.json"
    case_path.write_text(json.dumps(case))
    command = [kraken_python(), str(SCRIPT), str(case_path), str(out_path)]
    proc = subprocess.run(command, capture_output=True, text=True, timeout=timeout_s)
    if proc.returncode != 0:
        raise CrosscheckError(f"{' '.join(command)} exited with {proc.returncode}:\n{proc.stderr[-4000:]}")
    out = json.loads(out_path.read_text())
    for key in ("tl_db", "receiver_depth_m", "receiver_range_m"):
        out[key] = np.asarray(out[key], dtype=float)
    return out


def flat_area() -> Area:
    """A flat shallow bottom: 200 m of 1500 -> 1490 m/s water over the built-in areas' half-space
    (1600 m/s, 1.8 g/cm3, 0.8 dB/wavelength); no volume attenuation (KRAKEN's water has none)."""
    doc = envdata.load_area("munk-1000").to_dict()
    doc["area"] = {**doc["area"], "name": "kraken-flat"}
    doc["water"] = {"depth_m": 200.0, "ssp_depth_m": [0.0, 200.0], "ssp_speed_mps": [1500.0, 1490.0]}
    doc["observer"] = {"depth_m": 50.0}
    doc["classes"] = [{**doc["classes"][0], "depth_m": 50.0}]
    doc["propagation"] = {"absorption": "none"}
    return envdata.parse_area(doc, "kraken-flat")


def munk_area() -> Area:
    """ocean-deep: the canonical Munk profile to 5000 m; no volume attenuation."""
    doc = envdata.load_area("ocean-deep").to_dict()
    doc["area"] = {**doc["area"], "name": "kraken-munk"}
    doc["propagation"] = {"absorption": "none"}
    return envdata.parse_area(doc, "kraken-munk")


#: The two cases: area, frequency (Hz), source depth (m), receiver depths and ranges (m).
FLAT_CASE = (flat_area, 200.0, 50.0, np.arange(10.0, 191.0, 10.0), np.arange(2000.0, 10001.0, 100.0))
MUNK_CASE = (munk_area, 100.0, 100.0, np.arange(50.0, 4951.0, 100.0), np.arange(2000.0, 100001.0, 1000.0))


def both_tl_db(case, tmp_path: Path) -> tuple[np.ndarray, np.ndarray, dict]:
    """BELLHOP's incoherent TL (tmakit's settings: the area's beams, fan and mode) and KRAKEN's
    incoherent mode sum of one case, (depth, range) each, and KRAKEN's output."""
    make_area, freq_hz, source_m, depth_m, range_m = case
    area = make_area()
    spec = run_spec(area, title="kraken cross-check", freq_hz=freq_hz, source_depths_m=(source_m,),
                    receiver_depths_m=depth_m, ranges_m=range_m)
    bellhop = tl_from_pressure(run_env(env_text(area, spec)).field.pressure[0], area.propagation.tl_max_db)
    kraken = kraken_tl_db(kraken_case(area, freq_hz, source_m, depth_m, range_m), tmp_path)
    if not (np.allclose(kraken["receiver_range_m"], range_m, atol=1e-3)
            and np.allclose(kraken["receiver_depth_m"], depth_m, atol=1e-3)):
        raise CrosscheckError("KRAKEN's receivers are not the ones asked for")
    return bellhop, kraken["tl_db"], kraken


def windowed_tl_db(tl_db: np.ndarray, n: int) -> np.ndarray:
    """Intensity mean over consecutive windows of ``n`` ranges (the last partial one dropped), dB."""
    intensity = 10.0 ** (-np.asarray(tl_db, dtype=float) / 10.0)
    m = intensity.shape[1] // n * n
    return -10.0 * np.log10(intensity[:, :m].reshape(intensity.shape[0], -1, n).mean(axis=2))
