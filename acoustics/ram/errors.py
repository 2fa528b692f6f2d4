"""Errors raised by the RAM model: bad input, and a run that fails."""

from __future__ import annotations

from envdata.errors import InputError


class RamInputError(InputError):
    """A RAM environment, settings or receiver grid that is malformed or out of range."""


class RamRunError(RuntimeError):
    """easypyram failed on an input that passed the checks (e.g. its Pade root finder did not
    converge for this range step and number of Pade terms); the message quotes its own."""
