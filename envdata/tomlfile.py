"""TOML input files: reading one safely, and typed, key-checked access to its tables.

Shared by the area, scenario and perturbation files, so that each names the file, the table
and the key in its messages and rejects unknown keys the same way.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path
from typing import Any

from envdata.errors import AreaError
from envdata.files import read_input_bytes


class TomlTable:
    """Typed, key-checked access to one TOML table, with messages naming file and field."""

    def __init__(self, data: Any, where: str, source: str):
        self.source = source
        self.where = where
        if not isinstance(data, dict):
            raise AreaError(f"{source}: {where} must be a table, got {type(data).__name__}")
        self.data = dict(data)
        self.used: set[str] = set()

    def _fail(self, key: str, message: str) -> AreaError:
        return AreaError(f"{self.source}: {self.where} {key}: {message}")

    def value(self, key: str, default: Any = None, *, required: bool = False) -> Any:
        """The key's value as the TOML file gives it (any type), marked as used; ``default`` if
        absent, or AreaError if it is ``required``."""
        self.used.add(key)
        if key not in self.data:
            if required:
                raise AreaError(f"{self.source}: {self.where}: missing required key {key!r}")
            return default
        return self.data[key]

    def number(self, key: str, default: float | None = None, *, required: bool = True) -> float | None:
        value = self.value(key, default, required=required and default is None)
        if value is None:
            return None
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self._fail(key, f"must be a number, got {value!r}")
        value = float(value)
        if not math.isfinite(value):
            raise self._fail(key, f"must be finite, got {value}")
        return value

    def integer(self, key: str, default: int | None = None, *, required: bool = True) -> int | None:
        value = self.value(key, default, required=required and default is None)
        if value is None and not required:
            return None
        if isinstance(value, bool) or not isinstance(value, int):
            raise self._fail(key, f"must be an integer, got {value!r}")
        return value

    def boolean(self, key: str, default: bool) -> bool:
        value = self.value(key, default)
        if not isinstance(value, bool):
            raise self._fail(key, f"must be true or false, got {value!r}")
        return value

    def string(self, key: str, default: str | None = None, *, required: bool = True,
               choices: tuple[str, ...] | None = None) -> str | None:
        value = self.value(key, default, required=required and default is None)
        if value is None:
            return None
        if not isinstance(value, str):
            raise self._fail(key, f"must be a string, got {value!r}")
        if choices is not None and value not in choices:
            raise self._fail(key, f"must be one of {', '.join(choices)}, got {value!r}")
        return value

    def numbers(self, key: str, *, required: bool = True) -> list[float] | None:
        value = self.value(key, None, required=required)
        if value is None:
            return None
        if not isinstance(value, list) or not value:
            raise self._fail(key, f"must be a non-empty list of numbers, got {value!r}")
        out = []
        for item in value:
            if isinstance(item, bool) or not isinstance(item, (int, float)):
                raise self._fail(key, f"must be a list of numbers, got item {item!r}")
            if not math.isfinite(float(item)):
                raise self._fail(key, f"must be finite, got {item}")
            out.append(float(item))
        return out

    def has(self, key: str) -> bool:
        return key in self.data

    def done(self) -> None:
        unknown = sorted(set(self.data) - self.used)
        if unknown:
            raise AreaError(f"{self.source}: {self.where}: unknown key {unknown[0]!r}")

    def wrap(self, fn, *args, **kwargs):
        """Build a dataclass, prefixing its validation message with the file name."""
        try:
            return fn(*args, **kwargs)
        except AreaError as exc:
            raise AreaError(f"{self.source}: {exc}") from None


def read_toml(path: str | Path, what: str = "area file") -> tuple[dict[str, Any], str]:
    """Read a TOML file, turning every way it can be unreadable into an AreaError."""
    path = Path(path)
    source = str(path)
    raw = read_input_bytes(path, what, AreaError)
    if not raw.strip():
        raise AreaError(f"{source}: empty {what}")
    if b"\x00" in raw:
        raise AreaError(f"{source}: binary file, not a TOML {what}")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise AreaError(f"{source}: not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    try:
        return tomllib.loads(text), source
    except tomllib.TOMLDecodeError as exc:
        raise AreaError(f"{source}: TOML syntax error: {exc}") from None
    except RecursionError:
        raise AreaError(f"{source}: TOML nested too deeply to read") from None


