"""Reading BELLHOP3D's multi-bearing shade (.shd) file (the 2022 layout).

Layout (fixed-length records of ``4 * LRecl`` bytes, little-endian), as BELLHOP3D writes it:
record 1: int32 LRecl, 80-char title; 2: 10-char plot type; 3: int32 Nfreq, Ntheta, NSx, NSy,
NSz, NRz, NRr, float32 freq0, atten; 4: float64 frequencies; 5: float32 receiver bearings, deg
(counter-clockwise from +x, as given in the .env, sorted); 6-8: float32 source x, y (m) and
depths (m); 9: float32 receiver depths, m; 10: float32 receiver ranges, m; then one record of
NRr complex64 pressures per (source x, source y, bearing, source depth, receiver depth), in
that order. BELLHOP3D computes one frequency per run; a header with several frequencies is
read as blocks of that many records, the first one returned.

``acoustics.bellhop.shdfile.read_shd`` reads the same file's first bearing; this reader returns
every bearing.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from acoustics.bellhop.shdfile import COUNT_NAMES, read_header
from acoustics.errors import BellhopError


@dataclass(frozen=True)
class ShadeField3D:
    """The pressure field of one BELLHOP3D run (first frequency, first source x-y position).

    Attributes
    ----------
    title : str
    freq_hz : float
    bearing_deg : ndarray, shape (Ntheta,)
        Receiver bearings as BELLHOP3D holds them: deg counter-clockwise from +x (east).
    source_x_m, source_y_m : float
        The source's position in the box, m.
    source_depth_m : ndarray, shape (NSz,)
    receiver_depth_m : ndarray, shape (NRz,)
    range_m : ndarray, shape (NRr,)
    pressure : ndarray, complex64, shape (Ntheta, NSz, NRz, NRr)
        In incoherent mode |p|^2 is the summed beam intensity.
    """

    title: str
    freq_hz: float
    bearing_deg: np.ndarray
    source_x_m: float
    source_y_m: float
    source_depth_m: np.ndarray
    receiver_depth_m: np.ndarray
    range_m: np.ndarray
    pressure: np.ndarray


def read_shd3d(path: str | Path) -> ShadeField3D:
    """Read every bearing, source depth, receiver depth and range of a BELLHOP3D shade file.

    Raises
    ------
    BellhopError
        An empty, truncated or inconsistent file: a record length or an axis count that is not
        positive, an axis that does not fit its record, bearings that are not finite or not
        sorted, or fewer bytes than the header's counts promise.
    """
    path = Path(path)
    raw, rec, title, counts = read_header(path)
    nfreq, ntheta, nsx, nsy, nsz, nrz, nrr = (counts[name] for name in COUNT_NAMES)
    # each axis is one record: frequencies float64, the others float32; a pressure record holds
    # NRr complex64 values
    for name, nbytes in (("Nfreq", 8 * nfreq), ("Ntheta", 4 * ntheta), ("NSx", 4 * nsx), ("NSy", 4 * nsy),
                         ("NSz", 4 * nsz), ("NRz", 4 * nrz), ("NRr", 8 * nrr)):
        if nbytes > rec:
            raise BellhopError(f"{path}: shade file header is inconsistent: {name} = "
                               f"{counts[name]} does not fit a record of {rec} bytes")
    n_records = nsx * nsy * ntheta * nsz * nrz  # one frequency
    need = (10 + n_records) * rec
    if len(raw) < need:
        raise BellhopError(f"{path}: shade file is truncated: {len(raw)} bytes, the header's counts "
                           f"({', '.join(f'{k} = {v}' for k, v in counts.items())}) need {need}")
    freqs = np.frombuffer(raw, "<f8", nfreq, 3 * rec)
    theta = np.frombuffer(raw, "<f4", ntheta, 4 * rec).astype(float)
    if not np.all(np.isfinite(theta)) or np.any(np.diff(theta) < 0.0):  # BELLHOP3D sorts them
        raise BellhopError(f"{path}: shade file header is inconsistent: bearings {theta.tolist()} deg "
                           f"are not in increasing order")
    sx = float(np.frombuffer(raw, "<f4", 1, 5 * rec)[0])
    sy = float(np.frombuffer(raw, "<f4", 1, 6 * rec)[0])
    sz = np.frombuffer(raw, "<f4", nsz, 7 * rec).astype(float)
    rz = np.frombuffer(raw, "<f4", nrz, 8 * rec).astype(float)
    rr = np.frombuffer(raw, "<f4", nrr, 9 * rec).astype(float)
    first = ntheta * nsz * nrz  # the records of the first source x-y position
    block = np.frombuffer(raw, np.uint8, first * rec, 10 * rec).reshape(first, rec)
    p = block[:, : 8 * nrr].copy().view("<c8").reshape(ntheta, nsz, nrz, nrr)
    return ShadeField3D(title=title, freq_hz=float(freqs[0]), bearing_deg=theta, source_x_m=sx,
                        source_y_m=sy, source_depth_m=sz, receiver_depth_m=rz, range_m=rr, pressure=p)
