"""Install the BELLHOP executable into the virtual environment (run by ``make``).

First choice: the ``bellhop.exe`` compiled inside PyPI's ``aubellhop`` wheel (its executable
does not depend on the wheel's Python version). Where that wheel does not fit the platform or
does not run, build ``bellhop.exe`` from the same package's sdist with gfortran. Installs to
``<venv>/share/tmakit/bellhop/aubellhop/bin/bellhop.exe`` beside ``aubellhop.libs/`` (the
executable's RPATH is relative) and records the version in ``install.json``.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import platform
import shutil
import subprocess
import sys
import tarfile
import tempfile
import zipfile
from pathlib import Path

from acoustics.bellhop.exe import INSTALL_DIR, MANIFEST_NAME, installed_exe_path
from acoustics.bellhop.selftest import TINY_ENV

VERSION = "0.2.1"
WHEEL_PLATFORMS = {"x86_64": "manylinux_2_28_x86_64", "aarch64": "manylinux_2_28_aarch64"}



def pip_download(args: list[str], dest: Path) -> None:
    cmd = [sys.executable, "-m", "pip", "download", "--no-deps", "-q", "-d", str(dest),
           f"aubellhop=={VERSION}", *args]
    subprocess.run(cmd, check=True)


def works(exe: Path) -> bool:
    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "t.env").write_text(TINY_ENV)
        try:
            proc = subprocess.run([str(exe), "t"], cwd=tmp, capture_output=True, timeout=60)
        except OSError:
            return False
        return proc.returncode == 0 and (Path(tmp) / "t.shd").exists()


def from_wheel(dest: Path) -> str:
    plat = WHEEL_PLATFORMS.get(platform.machine())
    if plat is None:
        raise RuntimeError(f"no aubellhop wheel for {platform.machine()}")
    with tempfile.TemporaryDirectory() as tmp:
        pip_download(["--only-binary=:all:", "--python-version", "3.12", "--platform", plat], Path(tmp))
        wheel = next(Path(tmp).glob("*.whl"))
        with zipfile.ZipFile(wheel) as zf:
            for name in zf.namelist():
                if name == "aubellhop/bin/bellhop.exe" or name.startswith("aubellhop.libs/"):
                    zf.extract(name, dest)
    (dest / "aubellhop" / "bin" / "bellhop.exe").chmod(0o755)
    return "wheel"


def from_sdist(dest: Path) -> str:
    if shutil.which("gfortran") is None:
        print("gfortran not found; installing Debian's gfortran", file=sys.stderr)
        subprocess.run(["apt-get", "update", "-q"], check=True)
        subprocess.run(["apt-get", "install", "-y", "-q", "gfortran"], check=True)
    with tempfile.TemporaryDirectory() as tmp:
        pip_download(["--no-binary=:all:", "--python-version", "3.12"], Path(tmp))
        sdist = next(Path(tmp).glob("*.tar.gz"))
        with tarfile.open(sdist) as tf:
            tf.extractall(tmp, filter="data")
        fortran = next(Path(tmp).glob("aubellhop-*/fortran"))
        subprocess.run(["make", "FC=gfortran", "bellhop.exe"], cwd=fortran, check=True,
                       stdout=subprocess.DEVNULL)
        (dest / "aubellhop" / "bin").mkdir(parents=True, exist_ok=True)
        shutil.copy2(fortran / "bellhop.exe", dest / "aubellhop" / "bin" / "bellhop.exe")
    return "sdist, gfortran"


def link_on_path(exe: Path) -> None:
    """Put bellhop.exe in the venv's bin/ too, for tools (arlpy) that look for it on PATH."""
    link = Path(sys.prefix) / "bin" / "bellhop.exe"
    if link.is_symlink() or link.exists():
        link.unlink()
    link.symlink_to(exe)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--force", action="store_true", help="reinstall even if a working one is there")
    parser.add_argument("--from-source", action="store_true", help="build from the sdist with gfortran")
    args = parser.parse_args(argv)
    exe = installed_exe_path()
    if exe.exists() and works(exe) and not args.force:
        exe.touch()  # newer than the venv stamp, so make does not ask again
        link_on_path(exe)
        print(f"BELLHOP already installed: {exe}")
        return 0
    methods = [from_sdist] if args.from_source else [from_wheel, from_sdist]
    for method in methods:
        shutil.rmtree(INSTALL_DIR, ignore_errors=True)
        INSTALL_DIR.mkdir(parents=True)
        try:
            source = method(INSTALL_DIR)
        except (subprocess.CalledProcessError, RuntimeError, StopIteration, OSError) as exc:
            print(f"BELLHOP from {method.__name__[5:]} failed: {exc}", file=sys.stderr)
            continue
        if works(exe):
            digest = hashlib.sha256(exe.read_bytes()).hexdigest()
            (INSTALL_DIR / MANIFEST_NAME).write_text(json.dumps(
                {"version": VERSION, "source": source, "sha256": digest}, indent=1))
            link_on_path(exe)
            print(f"BELLHOP installed from {source}: {exe}")
            return 0
        print(f"BELLHOP from {method.__name__[5:]} does not run here", file=sys.stderr)
    print("error: could not install a working BELLHOP executable", file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main())
