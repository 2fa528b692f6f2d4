"""Reading BELLHOP's binary shade (.shd) file.

Layout (fixed-length records of ``4 * LRecl`` bytes, little-endian):
record 1: int32 LRecl, 80-char title; 2: 10-char plot type; 3: int32 Nfreq, Ntheta, NSx, NSy,
NSz, NRz, NRr, float32 freq0, atten; 4: float64 frequencies; 5: float32 bearings; 6-8: float32
source x, y, z; 9: float32 receiver depths; 10: float32 receiver ranges (m); then one record of
NRr complex64 pressures per (frequency, bearing, source depth, receiver depth), in that order.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from acoustics.errors import BellhopError


@dataclass(frozen=True)
class ShadeField:
    title: str
    freq_hz: float
    source_depth_m: np.ndarray   # (NSz,)
    receiver_depth_m: np.ndarray  # (NRz,)
    range_m: np.ndarray          # (NRr,)
    pressure: np.ndarray         # complex64 (NSz, NRz, NRr) for the first frequency and bearing


def read_shd(path: str | Path) -> ShadeField:
    path = Path(path)
    raw = path.read_bytes()
    if len(raw) < 4:
        raise BellhopError(f"{path}: shade file is empty or truncated ({len(raw)} bytes)")
    lrecl = int(np.frombuffer(raw, "<i4", 1, 0)[0])
    rec = 4 * lrecl
    if lrecl <= 0 or len(raw) < 10 * rec:
        raise BellhopError(f"{path}: shade file header is truncated ({len(raw)} bytes, record {rec})")
    title = raw[4:84].decode("ascii", "replace").strip()
    header = np.frombuffer(raw, "<i4", 7, 2 * rec)
    nfreq, ntheta, _nsx, _nsy, nsz, nrz, nrr = (int(v) for v in header)
    freqs = np.frombuffer(raw, "<f8", nfreq, 3 * rec)
    sz = np.frombuffer(raw, "<f4", nsz, 7 * rec).astype(float)
    rz = np.frombuffer(raw, "<f4", nrz, 8 * rec).astype(float)
    rr = np.frombuffer(raw, "<f4", nrr, 9 * rec).astype(float)
    nrec = nsz * nrz  # first frequency, first bearing
    need = (10 + nrec) * rec
    if len(raw) < need:
        raise BellhopError(f"{path}: shade file is truncated: {len(raw)} bytes, need {need}")
    block = np.frombuffer(raw, np.uint8, nrec * rec, 10 * rec).reshape(nrec, rec)
    p = block[:, : 8 * nrr].copy().view("<c8").reshape(nsz, nrz, nrr)
    del ntheta
    return ShadeField(title=title, freq_hz=float(freqs[0]) if nfreq else float("nan"),
                      source_depth_m=sz, receiver_depth_m=rz, range_m=rr, pressure=p)


def tl_from_pressure(pressure: np.ndarray, tl_max_db: float) -> np.ndarray:
    """TL = -20 lg |p|, dB; zero pressure (shadow) is capped at ``tl_max_db`` instead of inf."""
    mag = np.abs(pressure).astype(np.float64)
    floor = 10.0 ** (-tl_max_db / 20.0)
    return -20.0 * np.log10(np.maximum(mag, floor))
