"""Finding the BELLHOP executable and describing it.

Search order: the ``BELLHOP_EXE`` environment variable, the project's own install location
(``<venv>/share/tmakit/bellhop``, filled by ``python -m tools.install_bellhop``), then ``PATH``.
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
    found_by: str  # "BELLHOP_EXE", "install" or "PATH"
    version: str   # e.g. "aubellhop 0.2.1 (wheel)"; "unknown" for a binary we did not install
    sha256: str

    def describe(self) -> dict:
        return {"path": str(self.path), "found_by": self.found_by, "version": self.version,
                "sha256": self.sha256}


def installed_exe_path() -> Path:
    return INSTALL_DIR / "aubellhop" / "bin" / "bellhop.exe"


def find_bellhop() -> BellhopExe:
    """Locate BELLHOP or raise BellhopError saying where we looked."""
    env = os.environ.get("BELLHOP_EXE")
    if env:
        path = Path(env)
        if not (path.is_file() and os.access(path, os.X_OK)):
            raise BellhopError(f"BELLHOP_EXE={env}: not an executable file")
        return _describe(path, "BELLHOP_EXE")
    installed = installed_exe_path()
    if installed.is_file():
        return _describe(installed, "install")
    for name in ("bellhop.exe", "bellhop"):
        found = shutil.which(name)
        if found:
            return _describe(Path(found), "PATH")
    raise BellhopError(f"BELLHOP executable not found: BELLHOP_EXE is unset, {installed} does not exist "
                       f"and no bellhop.exe is on PATH; run 'make test' or "
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
            if info.get("sha256") == digest:
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
