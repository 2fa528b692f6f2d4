"""Reading BELLHOP's binary arrivals (.arr) file, written by a run of type 'a'.

A Fortran unformatted sequential file: each record is its payload between two int32 byte counts.
Records (2-D run): the tag ``'2D'``; float32 frequency; int32 NSz and float32 source depths;
int32 NRz and float32 receiver depths; int32 NRr and float32 receiver ranges (m); then per
source, one record with the largest arrival count, and per receiver depth and range (ranges
fastest) one record with the count ``n`` followed by ``n`` records of eight float32 each:
amplitude (spreading applied), phase (deg), delay (s, real and imaginary part: volume attenuation
is the imaginary part, |p| = A exp(omega Im tau)), launch angle and angle at the receiver (deg,
positive downward), and the numbers of surface and bottom reflections.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from acoustics.errors import BellhopError

#: One arrival's record: byte count, eight float32, byte count.
_ARRIVAL = np.dtype([("head", "<i4"), ("value", "<f4", 8), ("tail", "<i4")])
_ARRIVAL_BYTES = 32


@dataclass(frozen=True)
class Arrivals:
    """The arrivals of one source: receiver (depth, range) -> ``count`` arrivals, stored flat in
    receiver order (depth-major) in the per-arrival arrays."""

    freq_hz: float
    source_depth_m: float
    receiver_depth_m: np.ndarray  # (NRz,)
    range_m: np.ndarray           # (NRr,)
    count: np.ndarray             # int (NRz, NRr)
    amplitude: np.ndarray         # (n,) with spreading, at freq_hz, without volume attenuation
    phase_rad: np.ndarray         # (n,)
    delay_s: np.ndarray           # (n,) real part of the delay
    delay_imag_s: np.ndarray      # (n,) imaginary part (<= 0: volume attenuation)
    receiver_angle_deg: np.ndarray  # (n,) positive downward
    surface_bounces: np.ndarray   # (n,)

    @property
    def receiver_index(self) -> np.ndarray:
        """Flat receiver number (depth-major) of each arrival."""
        return np.repeat(np.arange(self.count.size), self.count.ravel())

    def intensity(self) -> np.ndarray:
        """|p|^2 of each arrival at the run frequency, volume attenuation included."""
        omega = 2.0 * np.pi * self.freq_hz
        return self.amplitude ** 2 * np.exp(2.0 * omega * self.delay_imag_s)


def read_arr(path: str | Path) -> list[Arrivals]:
    """The arrivals of every source of a binary 2-D arrivals file.

    Raises
    ------
    BellhopError
        A truncated or inconsistent file.
    """
    path = Path(path)
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise BellhopError(f"{path}: cannot read the arrivals file: {exc.strerror or exc}") from None
    pos = 0

    def record() -> bytes:
        nonlocal pos
        if pos + 4 > len(raw):
            raise BellhopError(f"{path}: arrivals file is truncated at byte {pos}")
        n = int(np.frombuffer(raw, "<i4", 1, pos)[0])
        if n < 0 or pos + 8 + n > len(raw):
            raise BellhopError(f"{path}: arrivals file is truncated or damaged at byte {pos}")
        payload = raw[pos + 4:pos + 4 + n]
        pos += n + 8
        return payload

    def axis(payload: bytes, name: str) -> np.ndarray:
        n = int(np.frombuffer(payload, "<i4", 1)[0]) if len(payload) >= 4 else -1
        if n < 1 or len(payload) < 4 + 4 * n:
            raise BellhopError(f"{path}: arrivals file header is inconsistent: {name} = {n}")
        return np.frombuffer(payload, "<f4", n, 4).astype(float)

    tag = record()
    if b"2D" not in tag:
        raise BellhopError(f"{path}: not a 2-D arrivals file (tag {tag!r})")
    freq = float(np.frombuffer(record(), "<f4", 1)[0])
    sz = axis(record(), "NSz")
    rz = axis(record(), "NRz")
    rr = axis(record(), "NRr")
    out = []
    for s in range(sz.size):
        record()  # the largest count
        count, v, pos = _arrivals_of_source(raw, pos, rz.size * rr.size, path)
        count = count.reshape(rz.size, rr.size)
        np.radians(v[1], out=v[1])
        out.append(Arrivals(freq_hz=freq, source_depth_m=float(sz[s]), receiver_depth_m=rz, range_m=rr,
                            count=count, amplitude=v[0], phase_rad=v[1], delay_s=v[2], delay_imag_s=v[3],
                            receiver_angle_deg=v[4], surface_bounces=v[5]))
    return out


#: The columns of an arrival's eight values that are kept: amplitude, phase, delay, its imaginary
#: part, receiver angle, surface bounces (not the source angle, 4, nor the bottom bounces, 7).
_KEPT = (0, 1, 2, 3, 5, 6)
_COUNT_RECORD = struct.Struct("<iii")  # byte count 4, the count, byte count 4


def _arrivals_of_source(raw: bytes, pos: int, receivers: int, path: Path) -> tuple[np.ndarray, np.ndarray, int]:
    """One source's receivers from byte ``pos``: their counts, the arrivals' values that the
    builder reads, ``(6, n)`` float64 with each row contiguous (amplitude, phase deg, delay, its
    imaginary part, receiver angle, surface bounces; receiver order), and the position after them.
    One pass over the count records finds the arrivals' blocks; the blocks are then taken out of
    the file's bytes at once. Rows, not columns: the reductions read each quantity whole, and the
    source angle and bottom bounces no one reads are left out (a large arrivals run's memory)."""
    counts = np.empty(receivers, dtype=np.int64)
    starts = np.empty(receivers, dtype=np.int64)
    unpack = _COUNT_RECORD.unpack_from
    for i in range(receivers):
        if pos + _COUNT_RECORD.size > len(raw):
            raise BellhopError(f"{path}: arrivals file is truncated at byte {pos}")
        head, n, tail = unpack(raw, pos)
        if head != 4 or tail != 4:
            raise BellhopError(f"{path}: arrivals file is damaged: a count record of {head} bytes at byte {pos}")
        if n < 0 or pos + _COUNT_RECORD.size + n * _ARRIVAL.itemsize > len(raw):
            raise BellhopError(f"{path}: arrivals file is truncated (receiver {i}, {n} arrivals)")
        starts[i], counts[i] = pos, n
        pos += _COUNT_RECORD.size + n * _ARRIVAL.itemsize
    if receivers == 0 or counts.sum() == 0:
        return counts, np.zeros((len(_KEPT), 0)), pos
    # the source's bytes as 4-byte words, less each count record's three: the arrivals' records
    first = int(starts[0])
    words = np.frombuffer(raw, "<i4", (pos - first) // 4, first)
    keep = np.ones(words.size, dtype=bool)
    keep[((starts - first) // 4)[:, None] + np.arange(3)] = False
    records = words[keep].reshape(-1, _ARRIVAL.itemsize // 4)
    bad = (records[:, 0] != _ARRIVAL_BYTES) | (records[:, -1] != _ARRIVAL_BYTES)
    if bad.any():
        receiver = int(np.searchsorted(np.cumsum(counts), int(np.argmax(bad)), side="right"))
        raise BellhopError(f"{path}: arrivals file is damaged (receiver {receiver})")
    del keep
    values = np.ascontiguousarray(records[:, 1:-1]).view("<f4")   # (n, 8) float32
    del records
    return counts, np.ascontiguousarray(values.T[list(_KEPT)], dtype=float), pos
