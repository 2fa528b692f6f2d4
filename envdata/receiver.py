"""Sonar files: another receiver in the same tables (planning with the sonar a planner has).

A grid's K(r) is the propagation from the target to the observer's depth; which sonar listens
there, and in what sea noise, enters only the detection rule (``acoustics.detection``). A sonar
file (docs/formats.md "Sonar files") holds a ``[sonar]`` table as an area file's and, optionally,
a ``[noise]`` table (the sea noise where that sonar listens; the area's when absent), with a
``name`` and a ``description``. Built-in ones live in ``envdata/sonars/``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from envdata.areafile import parse_noise, parse_sonar
from envdata.errors import AreaError
from envdata.files import builtin_names, builtin_or_path
from envdata.names import check_name
from envdata.noise import Noise
from envdata.sonar import Sonar
from envdata.tomlfile import TomlTable, read_toml


@dataclass(frozen=True, slots=True, kw_only=True)
class Receiver:
    """A sonar and, optionally, the sea noise it listens in.

    Attributes
    ----------
    name, description : str
    sonar : Sonar
    noise : Noise or None
        None: the area's noise.
    """

    name: str
    description: str
    sonar: Sonar
    noise: Noise | None = None


def builtin_sonar_names() -> list[str]:
    return builtin_names("sonars")


def load_receiver(name_or_path: str | Path) -> Receiver:
    """A built-in sonar by name or a sonar TOML file; AreaError naming the file and field on bad input."""
    path = builtin_or_path(name_or_path, "sonars", "sonar", AreaError)
    data, source = read_toml(path, "sonar file")
    return parse_receiver(data, source)


def parse_receiver(data: dict[str, Any], source: str = "<sonar>") -> Receiver:
    """Read a sonar-file document into a ``Receiver``."""
    t = TomlTable(data, "top level", source)
    name = t.wrap(check_name, t.string("name"), "name")
    description = t.string("description", "")
    if "sonar" not in data:
        raise AreaError(f"{source}: missing required table [sonar]")
    sonar = parse_sonar(t.value("sonar"), source)
    noise = parse_noise(t.value("noise"), source) if "noise" in data else None
    t.done()
    return Receiver(name=name, description=description, sonar=sonar, noise=noise)
