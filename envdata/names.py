"""Names that become file names or BELLHOP input: areas, classes, bands, scenarios.

They are ``[A-Za-z0-9._-]+``: no space, quote, slash or newline can reach a file name or the
quoted title line of a BELLHOP environment file.
"""

from __future__ import annotations

import re

from envdata.errors import AreaError

NAME_PATTERN = re.compile(r"[A-Za-z0-9._-]+")


def check_name(name: object, where: str) -> str:
    """Return ``name`` if it is a valid identifier, else raise AreaError naming ``where``."""
    if not isinstance(name, str) or not NAME_PATTERN.fullmatch(name):
        raise AreaError(f"{where}: must be letters, digits, '.', '_' or '-' (it names files and "
                        f"BELLHOP input), got {name!r}")
    return name
