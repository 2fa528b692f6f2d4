"""Where a command writes: checked before any work starts, so a bad path costs nothing.

An output path must be valid UTF-8, must not be a directory, must not sit under a regular file,
and its folder must be writable. An existing file is replaced only if it is the command's own
kind of file (a tmakit netCDF, a PNG, a track CSV, ...) or empty; anything else needs
``--force``, so that ``--out notes.txt`` never destroys notes.
"""

from __future__ import annotations

import os
import tempfile
from enum import StrEnum
from pathlib import Path

from envdata.errors import InputError


class Kind(StrEnum):
    """What a command writes; each knows how to recognise its own files."""

    NETCDF = "tmakit netCDF file"
    PNG = "PNG image"
    TRACK_CSV = "track CSV"
    MEASUREMENT_CSV = "measurement CSV"
    TRUTH_CSV = "truth CSV"
    ROUTE_CSV = "route CSV"
    CSV = "CSV file"
    JSON = "JSON file"
    AREA_TOML = "area file"


# first header cells that identify tmakit's CSV outputs
_CSV_HEADERS = {
    Kind.TRACK_CSV: ("t_s", "class", "x_m", "y_m", "range_m"),
    Kind.MEASUREMENT_CSV: ("t_s", "obs_x_m", "obs_y_m", "obs_depth_m", "bearing_deg"),
    Kind.TRUTH_CSV: ("t_s", "x_m", "y_m", "depth_m", "course_deg"),
    Kind.ROUTE_CSV: ("t_s", "obs_x_m", "obs_y_m", "bearing_deg"),
}


def _check_utf8(path: Path) -> None:
    try:
        str(path).encode("utf-8")
    except UnicodeEncodeError:
        shown = os.fsencode(path).decode("utf-8", "backslashreplace")
        raise InputError(f"{shown}: output path is not valid UTF-8; give a name in UTF-8") from None


def _check_folder(folder: Path, shown: Path) -> None:
    """The nearest existing ancestor of ``folder`` must be a writable directory."""
    probe = folder
    while not probe.exists():
        if probe.parent == probe:
            break
        if probe.is_symlink():  # a dangling link in the way
            raise InputError(f"{shown}: cannot write: {probe} is a broken link")
        probe = probe.parent
    if not probe.is_dir():
        raise InputError(f"{shown}: cannot write: {probe} is a file, not a folder")
    if not os.access(probe, os.W_OK | os.X_OK):
        raise InputError(f"{shown}: cannot write: no permission to write in {probe}")
    # permissions do not tell everything (a read-only or virtual file system, or root): try
    try:
        fd, name = tempfile.mkstemp(prefix=".tmakit-probe-", dir=probe)
    except OSError as exc:
        raise InputError(f"{shown}: cannot write: cannot create a file in {probe} "
                         f"({exc.strerror or exc})") from None
    os.close(fd)
    os.unlink(name)


def check_output_dir(path: str | os.PathLike) -> Path:
    """A folder that a command will write its files into (made if missing)."""
    p = Path(path)
    _check_utf8(p)
    if p.exists() and not p.is_dir():
        raise InputError(f"{p}: is a file, not a folder for the output files")
    _check_folder(p, p)
    return p


def check_output_file(path: str | os.PathLike, kind: Kind, *, force: bool = False) -> Path:
    """The path of one output file, refused before any work if it cannot or must not be written.

    Raises
    ------
    InputError
        Not UTF-8, a directory, under a regular file, in a folder without write permission,
        an existing non-regular file, or an existing file of another kind without ``force``.
    """
    p = Path(path)
    _check_utf8(p)
    if p.is_dir():
        raise InputError(f"{p}: is a directory; give a file name for the {kind}")
    _check_folder(p.parent, p)
    if p.exists():
        if not p.is_file():
            raise InputError(f"{p}: is not a regular file (a FIFO, device or socket); not "
                             f"replaced")
        if not force and p.stat().st_size > 0 and not is_kind(p, kind):
            raise InputError(f"{p}: exists and is not a {kind}; not replaced (--force replaces "
                             f"it)")
    return p


def is_kind(path: Path, kind: Kind) -> bool:
    """Whether an existing file looks like one ``kind`` writes."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(4096)
    except OSError:
        return False
    if kind is Kind.PNG:
        return head.startswith(b"\x89PNG\r\n\x1a\n")
    if kind is Kind.NETCDF:
        return _is_tmakit_netcdf(path, head)
    if kind is Kind.JSON:
        return head.lstrip()[:1] in (b"{", b"[")
    if kind is Kind.AREA_TOML:
        return b"[area]" in head
    text = head.decode("utf-8", "replace").lstrip("\ufeff")
    first = [cell.strip() for cell in text.splitlines()[0].split(",")] if text else []
    if kind is Kind.CSV:
        return len(first) > 1
    want = _CSV_HEADERS[kind]
    return tuple(first[:len(want)]) == want


def _is_tmakit_netcdf(path: Path, head: bytes) -> bool:
    if not (head.startswith(b"\x89HDF") or head.startswith(b"CDF")):
        return False
    try:
        import netCDF4

        with netCDF4.Dataset(path) as nc:
            return str(getattr(nc, "institution", "")) == "tmakit" or \
                str(getattr(nc, "title", "")).startswith("tmakit")
    except (OSError, RuntimeError, UnicodeError, ValueError):
        return False
