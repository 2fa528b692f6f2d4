"""Errors raised for bad input anywhere in tmakit.

Every message names the file, the field and the offending value with its unit, so that the
command line can print it as one ``error: ...`` line.
"""


class InputError(ValueError):
    """Bad input: a malformed file or a value out of range."""


class AreaError(InputError):
    """A malformed or unphysical area (or scenario) description."""
