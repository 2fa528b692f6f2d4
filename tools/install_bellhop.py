"""Install the BELLHOP and BELLHOP3D executables into the virtual environment (run by ``make``).

First choice: the ``bellhop.exe`` and ``bellhop3d.exe`` compiled inside PyPI's ``aubellhop``
wheel (its executables do not depend on the wheel's Python version). Where that wheel does not
fit the platform or does not run, build both from the same package's sdist with gfortran.
Installs to ``<venv>/share/tmakit/bellhop/aubellhop/bin/`` beside ``aubellhop.libs/`` (the
executables' RPATH is relative) and records the version and each executable's sha256 in
``install.json``. BELLHOP3D's Nx2D mode is the alternative route for bearing-dependent areas
(docs/nx2d.md).
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

from acoustics.bellhop.exe import INSTALL_DIR, MANIFEST_NAME, installed_exe3d_path, installed_exe_path
from acoustics.bellhop.selftest import TINY_CHANNEL, TINY_ENV

VERSION = "0.2.1"
WHEEL_PLATFORMS = {"x86_64": "manylinux_2_28_x86_64", "aarch64": "manylinux_2_28_aarch64"}
EXECUTABLES = ("bellhop.exe", "bellhop3d.exe")

# The 2-D self-test's isovelocity channel for BELLHOP3D: Nx2D, two bearings, a flat bottom.
TINY_ENV3D = "'tmakit self-test 3D'\n" + TINY_CHANNEL + """100.0 1600.0 0.0 1.8 0.8 /
1
0.0 /
1
0.0 /
1
50.0 /
2
10.0 90.0 /
3
0.1 0.5 1.0 /
2
0.0 90.0 /
'IG   2'
50
-30.0 30.0 /
1
0.0 0.0 /
0.0 1.1 1.1 101.0
"""
SELF_TESTS = {"bellhop.exe": TINY_ENV, "bellhop3d.exe": TINY_ENV3D}


def pip_download(args: list[str], dest: Path) -> None:
    cmd = [sys.executable, "-m", "pip", "download", "--no-deps", "-q", "-d", str(dest),
           f"aubellhop=={VERSION}", *args]
    subprocess.run(cmd, check=True)


def works(exe: Path) -> bool:
    """The executable runs its self-test environment and writes a shade file."""
    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "t.env").write_text(SELF_TESTS[exe.name])
        try:
            proc = subprocess.run([str(exe), "t"], cwd=tmp, capture_output=True, timeout=60)
        except OSError:
            return False
        return proc.returncode == 0 and (Path(tmp) / "t.shd").exists()


def installed() -> list[Path]:
    return [installed_exe_path(), installed_exe3d_path()]


def from_wheel(dest: Path) -> str:
    plat = WHEEL_PLATFORMS.get(platform.machine())
    if plat is None:
        raise RuntimeError(f"no aubellhop wheel for {platform.machine()}")
    with tempfile.TemporaryDirectory() as tmp:
        pip_download(["--only-binary=:all:", "--python-version", "3.12", "--platform", plat], Path(tmp))
        wheel = next(Path(tmp).glob("*.whl"))
        wanted = {f"aubellhop/bin/{name}" for name in EXECUTABLES}
        with zipfile.ZipFile(wheel) as zf:
            missing = wanted - set(zf.namelist())
            if missing:
                raise RuntimeError(f"{wheel.name} has no {', '.join(sorted(missing))}")
            for name in zf.namelist():
                if name in wanted or name.startswith("aubellhop.libs/"):
                    zf.extract(name, dest)
    for name in EXECUTABLES:
        (dest / "aubellhop" / "bin" / name).chmod(0o755)
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
        subprocess.run(["make", "FC=gfortran", *EXECUTABLES], cwd=fortran, check=True,
                       stdout=subprocess.DEVNULL)
        (dest / "aubellhop" / "bin").mkdir(parents=True, exist_ok=True)
        for name in EXECUTABLES:
            shutil.copy2(fortran / name, dest / "aubellhop" / "bin" / name)
    return "sdist, gfortran"


def link_on_path(exe: Path) -> None:
    """Put the executable in the venv's bin/ too, for tools (arlpy) that look for it on PATH."""
    link = Path(sys.prefix) / "bin" / exe.name
    if link.is_symlink() or link.exists():
        link.unlink()
    link.symlink_to(exe)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--force", action="store_true", help="reinstall even if a working one is there")
    parser.add_argument("--from-source", action="store_true", help="build from the sdist with gfortran")
    args = parser.parse_args(argv)
    exes = installed()
    if all(exe.exists() and works(exe) for exe in exes) and not args.force:
        for exe in exes:
            exe.touch()  # newer than the venv stamp, so make does not ask again
            link_on_path(exe)
        print(f"BELLHOP and BELLHOP3D already installed: {exes[0].parent}")
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
        broken = [exe.name for exe in exes if not works(exe)]
        if not broken:
            digests = {exe.name: hashlib.sha256(exe.read_bytes()).hexdigest() for exe in exes}
            (INSTALL_DIR / MANIFEST_NAME).write_text(json.dumps(
                {"version": VERSION, "source": source, "sha256": digests["bellhop.exe"],
                 "sha256_by_name": digests}, indent=1))
            for exe in exes:
                link_on_path(exe)
            print(f"BELLHOP and BELLHOP3D installed from {source}: {exes[0].parent}")
            return 0
        print(f"BELLHOP from {method.__name__[5:]}: {', '.join(broken)} does not run here", file=sys.stderr)
    print("error: could not install working BELLHOP and BELLHOP3D executables", file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main())
