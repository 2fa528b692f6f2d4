"""CTD casts: a CSV file of temperature and salinity against depth or pressure.

The cast gives an area its one sound-speed profile (``[water] cast = "cast.csv"``, DESIGN.md).
The file is CSV with a header row; ``#`` lines (before or between rows) and blank lines are
notes; extra columns are ignored. Columns:

- ``depth_m`` (m, positive down) or ``pressure_dbar`` (sea pressure, dbar; converted to depth
  with TEOS-10, ``gsw.z_from_p``, at the cast's latitude, the origin's); when both are present
  ``depth_m`` is used;
- ``temperature_c``: in-situ temperature, degC (ITS-90);
- ``salinity_psu``: practical salinity (PSS-78).

One row per depth, depths strictly increasing (a binned down-cast; an up-cast or a raw
scan-by-scan file must be binned first). Sea-Bird ``.cnv`` files are not read: export the
binned down-cast to CSV with these column names.
"""

from __future__ import annotations

import csv
import io
import math
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


def read_cast(path: str | Path, *, latitude_deg: float) -> TsProfile:
    """Read a CTD cast CSV into a T/S profile from the surface down.

    Parameters
    ----------
    path : path-like
        The CSV file (see the module docstring for its columns).
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
    if depth_column == "pressure_dbar":
        import gsw

        depth = -np.asarray(gsw.z_from_p(level, latitude_deg), dtype=float)
    else:
        depth = level
    temperature = np.asarray(values["temperature_c"])
    salinity = np.asarray(values["salinity_psu"])
    for name, series, lo, hi, unit_text in (("temperature_c", temperature, -2.5, 40.0, "degC"),
                                            ("salinity_psu", salinity, 0.0, 42.0, "")):
        bad = (series < lo) | (series > hi)
        if np.any(bad):
            i = int(np.argmax(bad))
            raise AreaError(f"{p}: line {lines[i]}: {name}: must be in [{lo:g}, {hi:g}]"
                            f"{' ' + unit_text if unit_text else ''}, got {series[i]}")
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
