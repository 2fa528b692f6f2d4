"""Input and output files: read only regular files, write so that nothing is left half-written.

Inputs: ``check_input_file`` refuses what is not a regular file (a directory, a FIFO, a device,
a socket), which would otherwise hang or read forever; ``read_input_bytes`` also refuses a file
larger than tmakit reads whole. Outputs: ``atomic_path`` writes one file through a temporary
file renamed on success; ``atomic_paths`` does the same for several files, all or none.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import stat
import tempfile
from collections.abc import Iterator, Sequence
from importlib import resources
from pathlib import Path

from envdata.errors import InputError

#: Largest text input (area, scenario and perturbation TOML; measurement and bearings CSV) that
#: tmakit reads whole, bytes. Real ones are kilobytes to a few megabytes.
MAX_TEXT_INPUT_BYTES = 256 * 2 ** 20


def _a(what: str) -> str:
    return f"an {what}" if what[:1].lower() in "aeio" else f"a {what}"


def check_input_file(path: str | os.PathLike, what: str,
                     error: type[ValueError] = InputError) -> Path:
    """The path of an input that exists and is a regular file, else ``error`` naming it.

    Parameters
    ----------
    path : path-like
    what : str
        What the file should be, for the message ("area file", "grid file", ...).
    error : ValueError subclass
        The exception raised (``AreaError``, ``GridFileError``, ...).
    """
    p = Path(path)
    try:
        st = os.stat(p)
    except FileNotFoundError:
        raise error(f"{p}: {what} not found") from None
    except NotADirectoryError:
        raise error(f"{p}: {what} not found (a folder on its path is a file)") from None
    except (OSError, ValueError) as exc:  # permission, name too long, NUL in the name
        reason = getattr(exc, "strerror", None) or str(exc)
        raise error(f"{p}: cannot read the {what}: {reason}") from None
    if stat.S_ISDIR(st.st_mode):
        raise error(f"{p}: is a directory, not {_a(what)}")
    if not stat.S_ISREG(st.st_mode):
        raise error(f"{p}: is not a regular file (a FIFO, device or socket), not {_a(what)}")
    return p


def read_input_bytes(path: str | os.PathLike, what: str, error: type[ValueError] = InputError,
                     max_bytes: int = MAX_TEXT_INPUT_BYTES) -> bytes:
    """The bytes of a regular input file of at most ``max_bytes``; ``error`` otherwise."""
    p = check_input_file(path, what, error)
    too_big = error(f"{p}: {what} is larger than the {max_bytes / 2 ** 20:.3g} MiB tmakit reads")
    try:
        if p.stat().st_size > max_bytes:
            raise too_big
        with open(p, "rb") as fh:
            raw = fh.read(max_bytes + 1)
    except OSError as exc:
        raise error(f"{p}: cannot read the {what}: {exc.strerror or exc}") from None
    if len(raw) > max_bytes:  # grew while read
        raise too_big
    return raw


def read_csv_text(path: str | os.PathLike, what: str, error: type[ValueError] = InputError) -> str:
    """The text of a CSV input file (`read_input_bytes`): refused when binary (a NUL byte) or not
    UTF-8, its byte-order mark dropped. ``error`` names the file."""
    raw = read_input_bytes(path, what, error)
    if b"\x00" in raw:
        raise error(f"{path}: not a text CSV file (binary data, NUL bytes)")
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise error(f"{path}: not a text CSV file (not UTF-8: {exc.reason} at byte {exc.start})") from None


def _temporary_beside(target: Path) -> Path:
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp_name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent)
    except OSError as exc:  # name the file the user asked for, not the temporary one
        raise OSError(exc.errno, f"cannot write ({exc.strerror or exc})", str(target)) from None
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp_name, 0o666 & ~umask)  # mkstemp makes 0600; give the file the usual permissions
    return Path(tmp_name)


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; rename it onto ``path`` only on success.

    The temporary file lives in the same directory so that the final ``os.replace`` is atomic.
    On any exception (an interrupt included) the temporary file is removed and ``path`` is left
    as it was.
    """
    with atomic_paths([path]) as (tmp,):
        yield tmp


@contextlib.contextmanager
def atomic_paths(paths: Sequence[str | os.PathLike]) -> Iterator[list[Path]]:
    """Yield temporary paths for several outputs and put them all in place, or none.

    Each target that already exists is kept aside (a hard link) until every rename has
    succeeded; if one rename fails, the files already put in place are rolled back, so the
    targets are all new or all as they were.
    """
    targets = [Path(p) for p in paths]
    temps: list[Path] = []
    done: list[tuple[Path, Path | None]] = []  # (target, its kept-aside original or None)
    try:
        for target in targets:
            temps.append(_temporary_beside(target))
        yield list(temps)
        for tmp, target in zip(temps, targets):
            backup = None
            if target.exists():
                backup = target.with_name(f".{target.name}.{os.getpid()}.orig")
                try:
                    os.link(target, backup)
                except OSError:  # a file system without hard links
                    shutil.copy2(target, backup)
            os.replace(tmp, target)
            done.append((target, backup))
    except BaseException:
        for target, backup in reversed(done):
            if backup is not None:
                os.replace(backup, target)
            else:
                target.unlink(missing_ok=True)
        done.clear()
        raise
    finally:
        for tmp in temps:
            tmp.unlink(missing_ok=True)
        for _, backup in done:
            if backup is not None:
                backup.unlink(missing_ok=True)


def builtin_names(folder: str) -> list[str]:
    """The names of the TOML files shipped in ``envdata/FOLDER`` (built-in areas, scenarios)."""
    return sorted(p.name[:-5] for p in (resources.files("envdata") / folder).iterdir() if p.name.endswith(".toml"))


def builtin_or_path(name_or_path: str | os.PathLike, folder: str, what: str,
                    error: type[ValueError] = InputError) -> Path:
    """A built-in file's path (``envdata/FOLDER/NAME.toml``) by its name, or the path given.

    ``error`` names the built-in ones when ``name_or_path`` is neither one of them nor a TOML
    path nor an existing file (``what``: "area", "scenario").
    """
    text = str(name_or_path)
    names = builtin_names(folder)
    if text in names:
        return Path(str(resources.files("envdata") / folder / f"{text}.toml"))
    path = Path(text)
    if path.suffix != ".toml" and not path.exists():
        raise error(f"{text}: no built-in {what} of that name (built-in: {', '.join(names)}) and no such file")
    return path
