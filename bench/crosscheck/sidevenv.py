"""The side venvs' interpreters (``make test`` makes each and names it in an environment variable):
the cross-checks run other programs (arlpy, KRAKEN, pyram's data) in their own processes."""

from __future__ import annotations

import os
from pathlib import Path


class CrosscheckError(RuntimeError):
    """A cross-check could not run: its side venv is missing, or the other program failed (a test
    that meets it fails, never skips)."""


def side_python(variable: str, venv: str, what: str) -> str:
    """The interpreter ``variable`` names; `CrosscheckError` when it is unset or not an executable
    (``venv``, ``what``: the venv ``make test`` makes and what it holds)."""
    python = os.environ.get(variable)
    if not python:
        raise CrosscheckError(f"{variable} is not set: run the suite with 'make test', which makes {venv} ({what}) "
                              f"and sets it")
    if not (Path(python).is_file() and os.access(python, os.X_OK)):
        raise CrosscheckError(f"{variable}={python} is not an executable file: 'make test' makes {venv}")
    return python
