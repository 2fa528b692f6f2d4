"""Errors raised by the acoustics package."""

from __future__ import annotations

from envdata.errors import InputError


class GridFileError(InputError):
    """A grid file that is missing, not netCDF, truncated, or lacks what the contract requires."""


class ObserverPositionError(InputError):
    """An observer position the tables cannot serve (outside an atlas's positions).

    ``index`` is the position's place in what was asked (from 0: a measurement file's row less
    one, a cycle); ``reason`` the message without it, for a caller that names the row its own way.
    """

    def __init__(self, index: int, reason: str):
        super().__init__(f"observer {index}: {reason}")
        self.index = int(index)
        self.reason = reason


class BellhopError(RuntimeError):
    """BELLHOP failed or could not be run.

    ``str(error)`` is one line that quotes BELLHOP's own message; ``prt_text`` holds the print
    file (or its tail), ``command`` the command line and ``returncode`` the exit status.
    """

    def __init__(self, message: str, *, prt_text: str = "", command: tuple[str, ...] = (),
                 returncode: int | None = None):
        super().__init__(message)
        self.prt_text = prt_text
        self.command = command
        self.returncode = returncode


class WorkerLostError(RuntimeError):
    """A worker process of a local build died before finishing its task (killed, or out of memory)."""
