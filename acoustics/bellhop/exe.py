"""Finding the BELLHOP and BELLHOP3D executables and describing them.

Search order: the ``BELLHOP_EXE`` (``BELLHOP3D_EXE``) environment variable, the project's own
install location (``<venv>/share/tmakit/bellhop``, filled by ``python -m tools.install_bellhop``
with both executables of one aubellhop release), then ``PATH``.
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import shutil
import sys
from dataclasses import dataclass
from pathlib import Path

from acoustics.errors import BellhopError

INSTALL_DIR = Path(sys.prefix) / "share" / "tmakit" / "bellhop"
MANIFEST_NAME = "install.json"


@dataclass(frozen=True, slots=True)
class BellhopExe:
    path: Path
    found_by: str  # "BELLHOP_EXE" (or "BELLHOP3D_EXE"), "install" or "PATH"
    version: str   # e.g. "aubellhop 0.2.1 (wheel)"; "unknown" for a binary we did not install
    sha256: str

    def describe(self) -> dict:
        return {"path": str(self.path), "found_by": self.found_by, "version": self.version,
                "sha256": self.sha256}


def installed_exe_path() -> Path:
    return INSTALL_DIR / "aubellhop" / "bin" / "bellhop.exe"


def installed_exe3d_path() -> Path:
    return INSTALL_DIR / "aubellhop" / "bin" / "bellhop3d.exe"


def find_bellhop() -> BellhopExe:
    """Locate BELLHOP or raise BellhopError saying where we looked."""
    return _find("BELLHOP", "BELLHOP_EXE", installed_exe_path(), ("bellhop.exe", "bellhop"))


def find_bellhop3d() -> BellhopExe:
    """Locate BELLHOP3D (its Nx2D mode traces all radials in one run) or raise BellhopError."""
    return _find("BELLHOP3D", "BELLHOP3D_EXE", installed_exe3d_path(), ("bellhop3d.exe", "bellhop3d"))


def _find(program: str, variable: str, installed: Path, names: tuple[str, ...]) -> BellhopExe:
    env = os.environ.get(variable)
    if env:
        path = Path(env)
        if not (path.is_file() and os.access(path, os.X_OK)):
            raise BellhopError(f"{variable}={env}: not an executable file")
        return _describe(path, variable)
    if installed.is_file():
        return _describe(installed, "install")
    for name in names:
        found = shutil.which(name)
        if found:
            return _describe(Path(found), "PATH")
    raise BellhopError(f"{program} executable not found: {variable} is unset, {installed} does not exist "
                       f"and no {names[0]} is on PATH; run 'make test' or "
                       f"'python -m tools.install_bellhop' to install it")


def _describe(path: Path, found_by: str) -> BellhopExe:
    path = path.resolve()
    stat = path.stat()
    digest = _sha256(str(path), stat.st_size, stat.st_mtime_ns)
    version = "unknown"
    manifest = path.parent.parent.parent / MANIFEST_NAME
    if manifest.is_file():
        try:
            info = json.loads(manifest.read_text())
            # "sha256" is bellhop.exe's; "sha256_by_name" names each installed executable
            known = {info.get("sha256"), *info.get("sha256_by_name", {}).values()}
            if digest in known:
                version = f"aubellhop {info['version']} ({info['source']})"
        except (ValueError, KeyError):
            pass
    return BellhopExe(path=path, found_by=found_by, version=version, sha256=digest)


@functools.lru_cache(maxsize=8)
def _sha256(path: str, size: int, mtime_ns: int) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()
