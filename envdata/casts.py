"""CTD casts: temperature and salinity against depth or pressure, from a CSV or a Sea-Bird ``.cnv`` file.

The cast gives an area its one sound-speed profile (``[water] cast = "cast.csv"`` or
``"cast.cnv"``, docs/formats.md "CTD casts"). Both kinds go through the same checks: depths strictly increasing,
the first no deeper than `MAX_CAST_TOP_M` (it is then continued up to the surface), T and S in
the sea's range.

CSV (any file that is not a ``.cnv``): a header row; ``#`` lines (before or between rows) and
blank lines are notes; extra columns are ignored. Columns:

- ``depth_m`` (m, positive down) or ``pressure_dbar`` (sea pressure, dbar; converted to depth
  with TEOS-10, ``gsw.z_from_p``, at the cast's latitude, the origin's); when both are present
  ``depth_m`` is used;
- ``temperature_c``: in-situ temperature, degC (ITS-90);
- ``salinity_psu``: practical salinity (PSS-78).

One row per depth, depths strictly increasing (a binned down-cast; an up-cast or a raw
scan-by-scan file must be binned first).

Sea-Bird ``.cnv`` (a file named ``*.cnv``, or one whose first line starts with ``* Sea-Bird``), as
SBE Data Processing writes it, binned or scan by scan; its table is read by the ``ctd`` package
(``ctd.from_cnv``). Columns, by Sea-Bird's short names (the others are ignored, secondary sensors
such as ``t190C`` and ``sal11`` too):

- ``depSM`` (depth, salt water, m) or else ``prDM`` (pressure, dbar, converted to depth as above);
- ``t090C`` (in-situ temperature, ITS-90) or else ``t068C`` (IPTS-68, converted to ITS-90 with
  ``gsw.t90_from_t68``: T68 / 1.00024);
- ``sal00`` (practical salinity);
- ``flag``, if present: a scan whose flag is not 0 (Loop Edit writes the file's ``bad_flag``) is
  dropped, and so is a scan holding the file's ``bad_flag`` (a missing value) in a column used.

Scans above the surface (negative depth: the CTD on deck) are dropped; the down-cast is kept, the
scans up to the deepest, the up-cast after it ignored. A file whose depths then increase strictly
(binned by SBE Data Processing) is used as it is; otherwise the scans are averaged in 1 m bins
centred on whole metres. The header's NMEA position and time are not used (the latitude is the
area's).
"""

from __future__ import annotations

import csv
import io
import math
import re
from pathlib import Path

import numpy as np

from envdata.errors import AreaError
from envdata.files import read_input_bytes
from envdata.ssp import TsProfile, check_ts

#: Deepest first sample of a cast, m: above it the shallowest sample's T and S are continued
#: to the surface (a CTD starts recording a few metres down); a cast starting deeper is refused.
MAX_CAST_TOP_M = 20.0
DEPTH_COLUMNS = ("depth_m", "pressure_dbar")
TS_COLUMNS = ("temperature_c", "salinity_psu")
#: The .cnv columns read, by Sea-Bird's short names, each in order of preference.
CNV_DEPTH_COLUMNS = ("depSM", "prDM")
CNV_TEMPERATURE_COLUMNS = ("t090C", "t068C")
CNV_SALINITY_COLUMN = "sal00"
#: Bins of a .cnv cast recorded scan by scan, m.
CNV_BIN_M = 1.0
_CNV_NAME = re.compile(r"#\s*name\s+\d+\s*=\s*([^:]*):")
_CNV_BAD_FLAG = re.compile(r"#\s*bad_flag\s*=\s*(\S+)")


def read_cast(path: str | Path, *, latitude_deg: float) -> TsProfile:
    """Read a CTD cast (CSV or Sea-Bird ``.cnv``) into a T/S profile from the surface down.

    Parameters
    ----------
    path : path-like
        The CSV or ``.cnv`` file (see the module docstring for their columns).
    latitude_deg : float
        Latitude of the cast, deg; pressure is converted to depth there.

    Returns
    -------
    TsProfile
        Depths from 0 m (the shallowest sample continued up to the surface), in-situ temperature
        and practical salinity, ``kind = "cast"``.

    Raises
    ------
    AreaError
        An unreadable file, a missing column, a value that is not a finite number, depths that do
        not increase, a first sample deeper than `MAX_CAST_TOP_M`, T or S outside the sea's range;
        the message names the file and the line.
    """
    p = Path(path)
    raw = read_input_bytes(p, "CTD cast", AreaError)
    if p.suffix.lower() == ".cnv" or raw.removeprefix(b"\xef\xbb\xbf").startswith(b"* Sea-Bird"):
        return _read_cnv(p, raw, latitude_deg)
    return _read_csv(p, raw, latitude_deg)


def _read_csv(p: Path, raw: bytes, latitude_deg: float) -> TsProfile:
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise AreaError(f"{p}: not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    if "\x00" in text:
        raise AreaError(f"{p}: binary file, not a CSV cast")
    rows = [(n, line) for n, line in enumerate(text.splitlines(), start=1)
            if line.strip() and not line.lstrip().startswith("#")]
    if not rows:
        raise AreaError(f"{p}: empty CTD cast (no header row)")
    header_line, header_text = rows[0]
    header = [name.strip() for name in next(csv.reader(io.StringIO(header_text)))]
    depth_column = next((name for name in DEPTH_COLUMNS if name in header), None)
    if depth_column is None:
        raise AreaError(f"{p}: line {header_line}: the header needs a depth_m or pressure_dbar column, "
                        f"got {', '.join(header)}")
    for name in TS_COLUMNS:
        if name not in header:
            raise AreaError(f"{p}: line {header_line}: the header needs a {name} column, "
                            f"got {', '.join(header)}")
    index = {name: header.index(name) for name in (depth_column, *TS_COLUMNS)}
    values: dict[str, list[float]] = {name: [] for name in index}
    lines: list[int] = []
    for n, line in rows[1:]:
        fields = next(csv.reader(io.StringIO(line)))
        if len(fields) != len(header):
            raise AreaError(f"{p}: line {n}: has {len(fields)} fields, the header has {len(header)}")
        for name, i in index.items():
            text_value = fields[i].strip()
            try:
                value = float(text_value)
            except ValueError:
                raise AreaError(f"{p}: line {n}: {name}: must be a number, got {text_value!r}") from None
            if not math.isfinite(value):
                raise AreaError(f"{p}: line {n}: {name}: must be finite, got {text_value!r}")
            values[name].append(value)
        lines.append(n)
    if len(lines) < 2:
        raise AreaError(f"{p}: a cast needs at least 2 rows of data, got {len(lines)}")

    level = np.asarray(values[depth_column])
    unit = "m" if depth_column == "depth_m" else "dbar"
    if np.any(level < 0.0):
        i = int(np.argmax(level < 0.0))
        raise AreaError(f"{p}: line {lines[i]}: {depth_column}: must be >= 0 {unit}, got {level[i]}")
    steps = np.diff(level) <= 0.0
    if np.any(steps):
        i = int(np.argmax(steps))
        raise AreaError(f"{p}: line {lines[i + 1]}: {depth_column}: must increase strictly down the cast "
                        f"(a binned down-cast), got {level[i]} {unit} then {level[i + 1]} {unit}")
    depth = _depth_from_pressure(level, latitude_deg) if depth_column == "pressure_dbar" else level
    temperature = np.asarray(values["temperature_c"])
    salinity = np.asarray(values["salinity_psu"])
    _check_ranges(p, TS_COLUMNS, temperature, salinity, lines)
    return _cast_profile(p, depth, temperature, salinity, lines)


def _depth_from_pressure(pressure_dbar: np.ndarray, latitude_deg: float) -> np.ndarray:
    import gsw

    return -np.asarray(gsw.z_from_p(pressure_dbar, latitude_deg), dtype=float)


def _check_ranges(p: Path, names: tuple[str, str], temperature: np.ndarray, salinity: np.ndarray,
                  lines) -> None:
    """T and S in the sea's range, else an AreaError naming the first line outside it."""
    for name, series, lo, hi, unit_text in ((names[0], temperature, -2.5, 40.0, "degC"),
                                            (names[1], salinity, 0.0, 42.0, "")):
        bad = (series < lo) | (series > hi)
        if np.any(bad):
            i = int(np.argmax(bad))
            raise AreaError(f"{p}: line {lines[i]}: {name}: must be in [{lo:g}, {hi:g}]"
                            f"{' ' + unit_text if unit_text else ''}, got {series[i]}")


def _cast_profile(p: Path, depth: np.ndarray, temperature: np.ndarray, salinity: np.ndarray,
                  lines) -> TsProfile:
    """The checks every cast ends with, then its profile from the surface down."""
    steps = np.diff(depth) <= 0.0
    if np.any(steps):  # a CSV has refused this on its own column already
        i = int(np.argmax(steps))
        raise AreaError(f"{p}: line {lines[i + 1]}: depths must increase strictly down the cast, "
                        f"got {depth[i]:g} m then {depth[i + 1]:g} m")
    if depth[0] > MAX_CAST_TOP_M:
        raise AreaError(f"{p}: line {lines[0]}: the cast starts at {depth[0]:.1f} m, deeper than "
                        f"{MAX_CAST_TOP_M:g} m: the water above it is unknown")
    if depth[0] > 0.0:  # the shallowest sample's T and S continue up to the surface
        depth = np.concatenate([[0.0], depth])
        temperature = np.concatenate([[temperature[0]], temperature])
        salinity = np.concatenate([[salinity[0]], salinity])
    check_ts(depth, temperature, salinity, str(p))
    return TsProfile(depth_m=tuple(float(v) for v in depth),
                     temperature_c=tuple(float(v) for v in temperature),
                     salinity_psu=tuple(float(v) for v in salinity), kind="cast")


def _number(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        return math.nan


def _read_cnv(p: Path, raw: bytes, latitude_deg: float) -> TsProfile:
    """A Sea-Bird .cnv cast (see the module docstring)."""
    if b"\x00" in raw:
        raise AreaError(f"{p}: binary file, not a Sea-Bird .cnv cast")
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:  # notes typed into the header on a Windows PC (cp1252)
        text = raw.decode("latin-1")
    lines = text.splitlines()
    if not any(line.strip() for line in lines):
        raise AreaError(f"{p}: empty file, not a Sea-Bird .cnv cast")
    end = next((k for k, line in enumerate(lines) if line.strip() == "*END*"), None)
    if end is None:
        raise AreaError(f"{p}: no *END* line closing the header: not a Sea-Bird .cnv file, or one cut short")
    header = [line.strip() for line in lines[:end]]
    names = [m.group(1).strip().strip("*") for line in header if (m := _CNV_NAME.match(line))]
    if not names:
        raise AreaError(f"{p}: the header names no columns (no '# name N = ...' lines)")
    listed = ", ".join(names)
    depth_name = next((name for name in CNV_DEPTH_COLUMNS if name in names), None)
    t_name = next((name for name in CNV_TEMPERATURE_COLUMNS if name in names), None)
    if t_name is None:
        raise AreaError(f"{p}: no temperature column (t090C or t068C) among {listed}")
    if CNV_SALINITY_COLUMN not in names:
        raise AreaError(f"{p}: no salinity column (sal00) among {listed}")
    if depth_name is None:
        raise AreaError(f"{p}: no depth or pressure column (depSM or prDM) among {listed}")
    scans = [(n, line.split()) for n, line in enumerate(lines[end + 1:], start=end + 2) if line.strip()]
    if not scans:
        raise AreaError(f"{p}: a header without data: no scans after *END*")
    for n, fields in scans:
        if len(fields) != len(names):
            raise AreaError(f"{p}: line {n}: has {len(fields)} values, the header names {len(names)} columns")

    # ctd parses the column names and the table. It is given the '#' header and the scans, not the
    # '*' lines: it parses the NMEA position and time there, which are not used, and raises on a
    # layout it does not expect
    given = [line for line in header if not line.startswith("*")] + ["*END*"]
    given += [lines[n - 1] for n, _ in scans]
    try:
        import ctd

        frame = ctd.from_cnv(io.StringIO("\n".join(given) + "\n"))
    except (ValueError, TypeError, IndexError, KeyError, AttributeError) as exc:
        reason = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
        raise AreaError(f"{p}: ctd could not read the .cnv table: {reason}") from None
    if len(frame) != len(scans):
        raise AreaError(f"{p}: ctd read {len(frame)} scans of the {len(scans)} after *END*")

    def column(name: str) -> np.ndarray:
        if name in frame.columns:
            return frame[name].to_numpy(dtype=float)
        # ctd moved it into the index, labelled "Pressure [dbar]" whatever it holds (and a depth
        # there may have been converted to pressure): taken back from the text
        i = names.index(name)
        return np.array([_number(fields[i]) for _, fields in scans])

    used = {name: column(name) for name in (depth_name, t_name, CNV_SALINITY_COLUMN)}
    line_numbers = np.array([n for n, _ in scans])
    keep = np.ones(len(scans), dtype=bool)
    if "flag" in names:  # ctd reads it as a bool, True for any text: taken from the text too
        i = names.index("flag")
        flag = np.array([_number(fields[i]) for _, fields in scans])
        keep &= flag == 0.0
    bad_flag = next((_number(m.group(1)) for line in header if (m := _CNV_BAD_FLAG.match(line))), math.nan)
    if math.isfinite(bad_flag):  # a missing value; ctd keeps it as a number
        for values in used.values():
            keep &= ~np.isclose(values, bad_flag, rtol=1e-6, atol=0.0)
    for name, values in used.items():
        bad = keep & ~np.isfinite(values)
        if np.any(bad):
            r = int(np.argmax(bad))
            raise AreaError(f"{p}: line {line_numbers[r]}: {name}: must be a finite number, "
                            f"got {scans[r][1][names.index(name)]!r}")
    level, temperature, salinity = (used[name][keep] for name in (depth_name, t_name, CNV_SALINITY_COLUMN))
    line_numbers = line_numbers[keep]
    if t_name == "t068C":
        import gsw

        temperature = np.asarray(gsw.t90_from_t68(temperature), dtype=float)
    depth = level if depth_name == "depSM" else _depth_from_pressure(level, latitude_deg)
    wet = depth >= 0.0  # scans above the surface: the CTD on deck
    depth, temperature, salinity, line_numbers = depth[wet], temperature[wet], salinity[wet], line_numbers[wet]
    if depth.size:  # the down-cast: the scans up to the deepest
        down = int(np.argmax(depth)) + 1
        depth, temperature, salinity, line_numbers = (a[:down] for a in (depth, temperature, salinity, line_numbers))
    _check_ranges(p, (t_name, CNV_SALINITY_COLUMN), temperature, salinity, line_numbers)
    if np.any(np.diff(depth) <= 0.0):  # scans, not bins: averaged in 1 m bins
        depth, temperature, salinity, line_numbers = _bin(depth, temperature, salinity, line_numbers)
    if depth.size < 2:
        raise AreaError(f"{p}: a cast needs at least 2 depths of good scans on the down-cast, got {depth.size}")
    return _cast_profile(p, depth, temperature, salinity, line_numbers)


def _bin(depth, temperature, salinity, line_numbers, size_m: float = CNV_BIN_M):
    """Mean T and S in bins of ``size_m`` centred on its multiples; each bin's first line."""
    centre, inverse = np.unique(np.floor(depth / size_m + 0.5), return_inverse=True)
    count = np.bincount(inverse)
    first = np.full(centre.size, np.iinfo(np.int64).max)
    np.minimum.at(first, inverse, line_numbers)
    return (centre * size_m, np.bincount(inverse, temperature) / count,
            np.bincount(inverse, salinity) / count, first)
