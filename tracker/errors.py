"""Errors for tracker inputs (measurement and bearing files, scenarios)."""

from envdata.errors import InputError


class MeasurementFileError(InputError):
    """A malformed measurement or bearings CSV, or values in it out of range."""


class LocateError(InputError):
    """Bearings that cannot give a position (too few, parallel lines, duplicate positions)."""
