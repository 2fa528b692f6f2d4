"""Running the BELLHOP executable on one environment file."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import tempfile
import threading
import time
from contextlib import AbstractContextManager
from dataclasses import dataclass
from pathlib import Path

from acoustics.bellhop.arrfile import Arrivals, read_arr
from acoustics.bellhop.exe import find_bellhop
from acoustics.bellhop.shdfile import ShadeField, read_shd
from acoustics.errors import BellhopError

BASE = "tmakit"


@dataclass(frozen=True)
class RunResult:
    field: ShadeField | None  # the TL field (.shd) of a TL run
    seconds: float  # wall time of the BELLHOP process alone
    prt_text: str
    arrivals: list[Arrivals] | None = None  # per source, of an arrivals run (.arr)


#: Default run limit: this many times BELLHOP's expected time, but at least `MIN_TIMEOUT_S`.
TIMEOUT_FACTOR = 50.0
MIN_TIMEOUT_S = 300.0
#: BELLHOP's cost per beam and receiver, s (measured: bench/bench_grids.py).
SECONDS_PER_BEAM_RECEIVER = 1.5e-9
#: Beams assumed for BELLHOP's automatic count (n_beams = 0), which grows with range x frequency.
AUTOMATIC_BEAMS = 100_000

_running: set[subprocess.Popen] = set()
_running_lock = threading.Lock()
_stopped = False  # set by an interrupt: no BELLHOP starts after it (`kill_running`)


def default_timeout_s(n_beams: int, n_receivers: int) -> float:
    """A generous limit for one run: `TIMEOUT_FACTOR` times its expected time, s."""
    beams = n_beams if n_beams > 0 else AUTOMATIC_BEAMS
    return max(MIN_TIMEOUT_S, TIMEOUT_FACTOR * SECONDS_PER_BEAM_RECEIVER * beams * n_receivers)


def kill_running(*, stop: bool = False) -> int:
    """Kill every BELLHOP process this process started that still runs; how many there were.

    Called when a command is interrupted, so that worker threads do not wait for their runs.
    With ``stop`` no BELLHOP starts after it (until `allow_runs`): the worker threads waiting for
    a slot behind the killed runs fail at once instead of starting theirs.
    """
    global _stopped
    with _running_lock:
        _stopped = _stopped or stop
        procs = list(_running)
    for proc in procs:
        _kill(proc)
    return len(procs)


def allow_runs() -> None:
    """Let BELLHOP start again after `kill_running` stopped it (a new command in this process)."""
    global _stopped
    with _running_lock:
        _stopped = False


def _kill(proc: subprocess.Popen) -> None:
    try:
        os.killpg(proc.pid, signal.SIGKILL)  # its own session: BELLHOP and anything it started
    except (ProcessLookupError, PermissionError):
        pass


def run_env(env: str, *, exe: str | Path | None = None, keep_dir: str | Path | None = None,
            timeout_s: float | None = None, files: dict[str, str] | None = None,
            slot: AbstractContextManager | None = None) -> RunResult:
    """Run BELLHOP on the .env text ``env`` in a temporary directory and read its .shd file
    (or, for an arrivals run, its binary .arr file).

    ``files`` maps an extension to the text of a file BELLHOP reads beside the .env (``"bty"``
    bathymetry, ``"ssp"`` range-dependent sound speed). With ``keep_dir`` the files are written
    there and kept (to debug); otherwise nothing is left behind. A run that outlives
    ``timeout_s`` seconds is killed. Raises BellhopError quoting BELLHOP's own message from the
    .prt file, or saying it was killed. ``slot`` (a semaphore, say) is held while BELLHOP runs and
    only then: the files are written before it and read after, beside another run's BELLHOP.
    """
    exe_path = Path(exe) if exe is not None else find_bellhop().path
    if keep_dir is not None:
        Path(keep_dir).mkdir(parents=True, exist_ok=True)
        return _run_in(Path(keep_dir), env, exe_path, timeout_s, files or {}, slot)
    with tempfile.TemporaryDirectory(prefix="tmakit-bellhop-") as tmp:
        return _run_in(Path(tmp), env, exe_path, timeout_s, files or {}, slot)


def _run_in(folder: Path, env: str, exe: Path, timeout_s: float | None,
            files: dict[str, str], slot: AbstractContextManager | None) -> RunResult:
    (folder / f"{BASE}.env").write_text(env)
    for suffix, text in files.items():
        (folder / f"{BASE}.{suffix}").write_text(text)
    command = (str(exe), BASE)
    with slot if slot is not None else contextlib.nullcontext():
        done, seconds = _bellhop(folder, command, exe, timeout_s)
    prt_path = folder / f"{BASE}.prt"
    prt = prt_path.read_text(errors="replace") if prt_path.exists() else ""
    shd_path, arr_path = folder / f"{BASE}.shd", folder / f"{BASE}.arr"
    if done.returncode != 0 or "FATAL ERROR" in prt or not (shd_path.exists() or arr_path.exists()):
        raise BellhopError(f"BELLHOP failed (exit {done.returncode}): {bellhop_message(prt, done)}",
                           prt_text=prt, command=command, returncode=done.returncode)
    if arr_path.exists():
        return RunResult(field=None, seconds=seconds, prt_text=prt, arrivals=read_arr(arr_path))
    return RunResult(field=read_shd(shd_path), seconds=seconds, prt_text=prt)


def _bellhop(folder: Path, command: tuple[str, str], exe: Path, timeout_s: float | None
             ) -> tuple[subprocess.CompletedProcess, float]:
    """BELLHOP's process in ``folder``, killed after ``timeout_s``; its outcome and wall time."""
    start = time.perf_counter()
    with _running_lock:  # started and registered at once: an interrupt kills it or it never starts
        if _stopped:
            raise BellhopError("BELLHOP was not started: the command was interrupted", command=command)
        try:
            proc = subprocess.Popen(command, cwd=folder, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                    start_new_session=True)
        except FileNotFoundError:
            raise BellhopError(f"BELLHOP executable {exe} not found", command=command) from None
        except PermissionError:
            raise BellhopError(f"BELLHOP executable {exe} is not executable", command=command) from None
        except OSError as exc:
            raise BellhopError(f"BELLHOP executable {exe} cannot run: {exc.strerror}",
                               command=command) from None
        _running.add(proc)
    try:
        try:
            stdout, stderr = proc.communicate(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            _kill(proc)
            proc.communicate()
            raise BellhopError(f"BELLHOP did not finish within {timeout_s:g} s and was killed "
                               f"([propagation] run_timeout_s sets the limit)",
                               command=command) from None
        except BaseException:  # interrupted: leave no BELLHOP behind
            _kill(proc)
            raise
    finally:
        with _running_lock:
            _running.discard(proc)
    seconds = time.perf_counter() - start
    return subprocess.CompletedProcess(command, proc.returncode, stdout, stderr), seconds


def bellhop_message(prt: str, proc: subprocess.CompletedProcess | None = None) -> str:
    """BELLHOP's own error message: the lines after '*** FATAL ERROR ***' in the .prt file."""
    lines = [line.strip() for line in prt.splitlines()]
    if "*** FATAL ERROR ***" in lines:
        i = lines.index("*** FATAL ERROR ***")
        text = [ln for ln in lines[i + 1:i + 4] if ln]
        prefix = "Generated by program or subroutine:"
        if text and text[0].startswith(prefix):
            text[0] = text[0][len(prefix):].strip() + ":"
        return " ".join(text)
    stderr = (proc.stderr.decode(errors="replace") if proc is not None else "").strip()
    first = next((ln for ln in stderr.splitlines() if ln.strip()), "")
    tail = " | ".join(ln for ln in lines[-3:] if ln)
    return (first or "no message") + (f" (print file ends: {tail})" if tail else "")
