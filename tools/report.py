"""What every command returns: a human-readable summary and the same facts as JSON data."""

from __future__ import annotations

import sys
from dataclasses import dataclass, field
from typing import Any


@dataclass(frozen=True, slots=True)
class Report:
    summary: str
    data: dict[str, Any] = field(default_factory=dict)


def want_progress(args) -> bool:
    """Progress bars go to stderr only for a terminal, never with --json, always with --progress."""
    if getattr(args, "progress", False):
        return True
    if getattr(args, "json", False):
        return False
    return sys.stderr.isatty()
