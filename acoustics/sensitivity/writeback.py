"""Writing a measured ``k_error_sd_db`` back into a copy of an area file, comments and layout kept."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

from envdata.areafile import load_area
from envdata.errors import InputError
from envdata.files import atomic_path

SECTION = re.compile(r"^\s*\[")
K_ERROR_KEY = re.compile(r"^\s*k_error_sd_db\s*=")
NAME_KEY = re.compile(r"^\s*name\s*=")


def write_k_error(area_file: str | Path, values: dict[str, float], out: str | Path, *,
                  atomic: bool = True) -> Path:
    """Copy the area TOML ``area_file`` to ``out`` with each class's ``k_error_sd_db`` replaced.

    Comments and layout are kept; a class without the key gets it after its ``name`` line. The
    copy is re-read with ``envdata.load_area`` before it replaces ``out``.

    Parameters
    ----------
    area_file : path
        The area TOML to copy.
    values : dict of str to float
        ``k_error_sd_db`` per class name, dB (``k_error_by_class``); written to 0.01 dB.
    out : path
        The copy to write.
    atomic : bool
        Write through a temporary file renamed on success (default); without, straight to
        ``out`` (for a caller that renames several files together).

    Returns
    -------
    Path
        ``out``.
    """
    text = Path(area_file).read_text(encoding="utf-8")
    lines = text.splitlines(keepends=True)
    starts = [i for i, line in enumerate(lines) if SECTION.match(line)] + [len(lines)]
    done = set()
    out_lines = lines[:starts[0]]
    for a, b in zip(starts[:-1], starts[1:]):
        block = lines[a:b]
        if block[0].strip().startswith("[[classes]]"):
            name = tomllib.loads("".join(block[1:])).get("name")
            if name in values:
                value_line = f"k_error_sd_db = {values[name]:.2f}  # measured by tmakit sensitivity\n"
                hits = [j for j, line in enumerate(block) if K_ERROR_KEY.match(line)]
                if hits:
                    block[hits[0]] = value_line
                else:
                    at = next(j for j, line in enumerate(block) if NAME_KEY.match(line))
                    block.insert(at + 1, value_line)
                done.add(name)
        out_lines += block
    missing = sorted(set(values) - done)
    if missing:
        raise InputError(f"{area_file}: no [[classes]] entry named {missing[0]!r} to write k_error_sd_db into")
    out = Path(out)
    if not atomic:
        _write_checked(out, "".join(out_lines), values, area_file)
        return out
    with atomic_path(out) as tmp:
        _write_checked(tmp, "".join(out_lines), values, area_file)
    return out


def _write_checked(path: Path, text: str, values: dict[str, float], area_file) -> None:
    """Write the copy and read it back with the area loader: it must carry the values."""
    path.write_text(text, encoding="utf-8")
    area = load_area(path)
    for cls in area.classes:
        if cls.name in values and abs(cls.k_error_sd_db - round(values[cls.name], 2)) > 1e-9:
            raise InputError(f"{area_file}: could not write k_error_sd_db of class {cls.name!r}")
