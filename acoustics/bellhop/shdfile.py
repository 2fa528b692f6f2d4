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


#: Largest count a shade-file header may give for any axis (a larger one is a damaged file).
MAX_COUNT = 50_000_000


#: The axis counts of a shade file's third record, in order.
COUNT_NAMES = ("Nfreq", "Ntheta", "NSx", "NSy", "NSz", "NRz", "NRr")


def read_header(path: Path) -> tuple[bytes, int, str, dict[str, int]]:
    """A shade file's bytes, record length (bytes), title and axis counts, the counts checked.

    Shared by the 2-D reader here and the BELLHOP3D one (``shd3d``): both write this header.
    """
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise BellhopError(f"{path}: cannot read the shade file: {exc.strerror or exc}") from None
    if len(raw) < 4:
        raise BellhopError(f"{path}: shade file is empty or truncated ({len(raw)} bytes)")
    lrecl = int(np.frombuffer(raw, "<i4", 1, 0)[0])
    rec = 4 * lrecl
    if lrecl <= 0 or len(raw) < 10 * rec:
        raise BellhopError(f"{path}: shade file header is truncated ({len(raw)} bytes, record {rec})")
    title = raw[4:84].decode("ascii", "replace").strip()
    counts = dict(zip(COUNT_NAMES, (int(v) for v in np.frombuffer(raw, "<i4", 7, 2 * rec))))
    for name, value in counts.items():
        if not 1 <= value <= MAX_COUNT:
            raise BellhopError(f"{path}: shade file header is inconsistent: {name} = {value}")
    return raw, rec, title, counts


def read_shd(path: str | Path) -> ShadeField:
    """Read the first frequency and bearing of a shade file.

    Raises
    ------
    BellhopError
        An empty, truncated or inconsistent file: a record length or an axis count that is not
        positive, an axis that does not fit its record, or fewer bytes than the header promises.
    """
    path = Path(path)
    raw, rec, title, counts = read_header(path)
    nfreq, nsz, nrz, nrr = counts["Nfreq"], counts["NSz"], counts["NRz"], counts["NRr"]
    # each axis is one record: frequencies float64, the others float32; a pressure record
    # holds NRr complex64 values
    for name, nbytes in (("Nfreq", 8 * nfreq), ("Ntheta", 4 * counts["Ntheta"]), ("NSz", 4 * nsz),
                         ("NRz", 4 * nrz), ("NRr", 8 * nrr)):
        if nbytes > rec:
            raise BellhopError(f"{path}: shade file header is inconsistent: {name} = "
                               f"{counts[name]} does not fit a record of {rec} bytes")
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
    return ShadeField(title=title, freq_hz=float(freqs[0]),
                      source_depth_m=sz, receiver_depth_m=rz, range_m=rr, pressure=p)


def tl_from_pressure(pressure: np.ndarray, tl_max_db: float) -> np.ndarray:
    """TL = -20 lg |p|, dB; zero pressure (shadow) is capped at ``tl_max_db`` instead of inf."""
    mag = np.abs(pressure).astype(np.float64)
    floor = 10.0 ** (-tl_max_db / 20.0)
    return -20.0 * np.log10(np.maximum(mag, floor))
