"""The ``tmakit`` command line: argparse subcommands, each calling one library function.

Bad input ends a command with exit status 2 and one ``error: ...`` line on stderr (no traceback);
results go to files and a summary (or, with ``--json``, one JSON object) to stdout.
"""

from __future__ import annotations

import argparse
import json
import logging
import sys
from collections.abc import Sequence

from acoustics.errors import BellhopError
from envdata.errors import InputError
from tools import (areas_cmd, demo_cmd, doctor_cmd, experiment_cmd, grids_cmd, locate_cmd, sensitivity_cmd,
                   simulate_cmd, track_cmd)

COMMAND_MODULES = (doctor_cmd, areas_cmd, grids_cmd, sensitivity_cmd, simulate_cmd, track_cmd, experiment_cmd,
                   locate_cmd, demo_cmd)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="tmakit", parents=[_common_options(argparse.SUPPRESS)],
        description="Propagation tables and passive-sonar target motion analysis.")
    parser.set_defaults(json=False, progress=False, verbose=0)
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
    return common


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.WARNING - 10 * min(args.verbose, 2), stream=sys.stderr,
                        format="%(levelname)s %(name)s: %(message)s")
    try:
        report = args.func(args)
    except (InputError, BellhopError) as exc:
        message = " ".join(str(exc).split("\n")[0].split()) if isinstance(exc, InputError) else str(exc)
        print(f"error: {message}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("error: interrupted; finished work is kept and a rerun resumes it", file=sys.stderr)
        return 130
    if args.json:
        print(json.dumps(report.data, default=_jsonable))
    else:
        print(report.summary)
    return 0


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


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
