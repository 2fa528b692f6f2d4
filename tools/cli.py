"""The ``tmakit`` command line: argparse subcommands, each calling one library function.

Bad input ends a command with exit status 2 and one ``error: ...`` line on stderr (no traceback);
results go to files and a summary (or, with ``--json``, one JSON object) to stdout. ``main`` is
the one place that turns failures into that line (README, after the command list).
"""

from __future__ import annotations

import argparse
import gc
import json
import logging
import os
import signal
import sys
from collections.abc import Sequence

from acoustics.errors import BellhopError, WorkerLostError
from acoustics.ram.errors import RamRunError
from envdata.errors import InputError
from envdata.limits import TooLargeError, memory_limit
from tools import (
    areas_cmd,
    atlas_cmd,
    demo_cmd,
    doctor_cmd,
    experiment_cmd,
    grids_cmd,
    locate_cmd,
    plan_cmd,
    sensitivity_cmd,
    simulate_cmd,
    track_cmd,
)

COMMAND_MODULES = (doctor_cmd, areas_cmd, grids_cmd, atlas_cmd, sensitivity_cmd, simulate_cmd, track_cmd,
                   plan_cmd, experiment_cmd, locate_cmd, demo_cmd)


class _Parser(argparse.ArgumentParser):
    """argparse with the command line's one-line errors: ``error: tmakit track: ...`` and exit
    status 2, without the usage block argparse prints first (``--help`` still shows it)."""

    def error(self, message: str):
        self.exit(2, f"error: {self.prog}: {message} (--help shows the usage)\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="tmakit", parents=[_common_options(argparse.SUPPRESS)],
        description="Propagation tables and passive-sonar target motion analysis.")
    parser.set_defaults(json=False, progress=False, verbose=0, max_gib=None)
    # subcommands take the same options anywhere on the line; SUPPRESS keeps a subparser from
    # resetting what an earlier position already set
    common = _common_options(argparse.SUPPRESS)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for module in COMMAND_MODULES:
        module.register(sub, common)
    return parser


def _common_options(default) -> argparse.ArgumentParser:
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--json", action="store_true", default=default,
                        help="print the result as one JSON object")
    common.add_argument("--progress", action="store_true", default=default,
                        help="show progress bars even when stderr is not a terminal")
    common.add_argument("-v", "--verbose", action="count", default=default, help="more log output")
    common.add_argument("--max-gib", type=float, default=default, metavar="GIB",
                        help="memory a piece of work may take, GiB (default: $TMAKIT_MAX_GIB, else half "
                             "the machine's)")
    return common


#: The environment variable that gives --max-gib its default.
MAX_GIB_VARIABLE = "TMAKIT_MAX_GIB"


def _max_gib(args) -> tuple[float | None, str]:
    """The memory limit the command line sets, GiB, and how a message names it: --max-gib, else
    TMAKIT_MAX_GIB, else none (the library's default, half the machine's memory)."""
    if args.max_gib is not None:
        return args.max_gib, "--max-gib"
    text = os.environ.get(MAX_GIB_VARIABLE)
    if not text:
        return None, ""
    try:
        return float(text), f"{MAX_GIB_VARIABLE}={text}"
    except ValueError:
        raise InputError(f"{MAX_GIB_VARIABLE}={text!r}: must be a number of GiB") from None


class Terminated(KeyboardInterrupt):
    """SIGTERM (what batch systems send) as an interrupt, so the same clean-up runs."""


def _on_signal(signum, frame) -> None:
    """SIGTERM, and SIGINT where Python's own handler had it: kill the model runs under way and
    start no more before anything waits for them (a worker pool waits for its threads), then
    interrupt."""
    _kill_running_models(stop=True)
    raise Terminated() if signum == signal.SIGTERM else KeyboardInterrupt()


def main(argv: Sequence[str] | None = None) -> int:
    """Run one command; return its exit status.

    Every failure a user can cause by what they pass ends here as one ``error: ...`` line on
    stderr and status 2: bad input (``InputError``: files, values, sizes), a BELLHOP or RAM
    failure or time-out, a lost worker process, and an operating-system error on an input or
    output. SIGINT and SIGTERM end with 130 and 143, after killing the runs under way; finished work that a rerun
    resumes is kept, and no half-written output is left.
    """
    for stream in (sys.stdout, sys.stderr):
        if hasattr(stream, "reconfigure"):
            stream.reconfigure(errors="backslashreplace")  # odd bytes in a path never crash a print
    parser = build_parser()
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.WARNING - 10 * min(args.verbose, 2), stream=sys.stderr,
                        format="%(levelname)s %(name)s: %(message)s")
    previous = {}
    if _main_thread():
        _allow_model_runs()
        previous[signal.SIGTERM] = signal.signal(signal.SIGTERM, _on_signal)
        if signal.getsignal(signal.SIGINT) is signal.default_int_handler:  # not an ignored one
            previous[signal.SIGINT] = signal.signal(signal.SIGINT, _on_signal)
    try:
        gib, source = _max_gib(args)
        with memory_limit(gib, source):
            report = args.func(args)
        if args.json:
            print(json.dumps(report.data, default=_jsonable))
        else:
            print(report.summary)
        sys.stdout.flush()
    except KeyboardInterrupt as exc:
        _kill_running_models()
        signum = signal.SIGTERM if isinstance(exc, Terminated) else signal.SIGINT
        print("error: interrupted; finished work is kept and a rerun resumes it", file=sys.stderr)
        return 128 + int(signum)
    except BrokenPipeError:
        # the reader of our output went away (``tmakit ... | head``): stop quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 128 + int(signal.SIGPIPE)
    except TooLargeError as exc:
        print(f"error: {_one_line(str(exc))}; --max-gib raises it on a bigger machine", file=sys.stderr)
        return 2
    except (InputError, BellhopError, RamRunError, WorkerLostError) as exc:
        print(f"error: {_one_line(str(exc))}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"error: {_one_line(_os_message(exc))}", file=sys.stderr)
        return 2
    except MemoryError:
        print("error: out of memory; the work is larger than this machine (see --max-gib)",
              file=sys.stderr)
        return 2
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
    return 0


def _kill_running_models(stop: bool = False) -> None:
    """Kill the BELLHOP runs under way (with ``stop``, and start no more); a command that never
    ran BELLHOP never imported its runner (commands import what they need when they run), and
    then there is nothing to kill."""
    if (runner := _bellhop_runner()) is not None:
        runner.kill_running(stop=stop)


def _allow_model_runs() -> None:
    """A new command in this process may start BELLHOP again after an interrupted one."""
    if (runner := _bellhop_runner()) is not None:
        runner.allow_runs()


def _bellhop_runner():
    """``acoustics.bellhop.runner`` if this process imported it, else None."""
    return sys.modules.get("acoustics.bellhop.runner")


def _main_thread() -> bool:
    import threading

    return threading.current_thread() is threading.main_thread()


def _one_line(text: str) -> str:
    return " ".join(text.split("\n")[0].split()) or "failed"


def _os_message(exc: OSError) -> str:
    """``path: reason`` of an operating-system error on a file tmakit was given."""
    reason = (exc.strerror or str(exc)).rstrip(".")
    reason = reason[:1].lower() + reason[1:]
    names = [str(n) for n in (exc.filename, exc.filename2) if n is not None]
    return f"{' -> '.join(names)}: {reason}" if names else reason


def _jsonable(value):
    try:
        import numpy as np
        if isinstance(value, np.generic):
            return value.item()
        if isinstance(value, np.ndarray):
            return value.tolist()
    except ImportError:  # pragma: no cover - numpy is a dependency
        pass
    return str(value)


def run() -> None:
    """The ``tmakit`` script: `main`, then the interpreter's exit with its objects frozen
    (`gc.freeze`). Python's teardown otherwise sweeps every object xarray, dask, pandas and scipy
    left for its collector again and again while it clears their modules: 0.4 s of every command
    that built or read a grid, 0.05 s frozen (by hand, a process holding a grid file's dataset).
    Exit handlers and finalizers run as before; only the collector's passes are skipped."""
    status = main()
    gc.freeze()
    sys.exit(status)


if __name__ == "__main__":  # pragma: no cover
    run()
