"""Physical bounds on inputs and the memory a piece of work may take.

Positions beyond 20 000 km or times beyond 100 years are typing or unit mistakes, not sea
areas. Work whose arrays would not fit the machine (a grid, a scenario, a study, an experiment)
is refused before it starts, with the size it would take: the limit is half the machine's
memory unless ``TMAKIT_MAX_GIB`` (the command line's ``--max-gib``) says otherwise.
"""

from __future__ import annotations

import math
import os

from envdata.errors import InputError

#: Largest distance from the origin of any position, m (half the Earth's circumference).
MAX_POSITION_M = 2.0e7
#: Largest time, s (100 years).
MAX_TIME_S = 100 * 365.25 * 86400.0
#: Environment variable that sets the memory limit, GiB.
LIMIT_VARIABLE = "TMAKIT_MAX_GIB"

GIB = 2.0 ** 30


class TooLargeError(InputError):
    """Work that would need more memory than the limit allows."""


def machine_memory_bytes() -> float:
    """Physical memory of this machine, bytes (8 GiB when the system does not say)."""
    try:
        return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):
        return 8.0 * GIB


def memory_limit_bytes() -> tuple[float, str]:
    """The memory limit, bytes, and where it comes from (for messages)."""
    text = os.environ.get(LIMIT_VARIABLE)
    if text:
        try:
            value = float(text)
        except ValueError:
            raise InputError(f"{LIMIT_VARIABLE}={text!r}: must be a number of GiB") from None
        if not (math.isfinite(value) and value > 0):
            raise InputError(f"{LIMIT_VARIABLE}={text!r}: must be a positive number of GiB")
        return value * GIB, f"--max-gib / {LIMIT_VARIABLE}"
    return 0.5 * machine_memory_bytes(), "half this machine's memory"


def check_memory(nbytes: float, what: str) -> None:
    """Refuse work needing ``nbytes`` of memory beyond the limit, saying how much it needs.

    Raises
    ------
    TooLargeError
        ``what`` needs more than the limit; the message gives both in GiB and how to raise it.
    """
    limit, why = memory_limit_bytes()
    if not nbytes <= limit:  # also refuses NaN
        raise TooLargeError(f"{what} would need {nbytes / GIB:.3g} GiB of memory, more than the "
                            f"limit of {limit / GIB:.3g} GiB ({why}); --max-gib raises it on a "
                            f"bigger machine")


def check_position(value_m: float, where: str) -> None:
    """Refuse a coordinate further than `MAX_POSITION_M` from the origin."""
    if not abs(value_m) <= MAX_POSITION_M:
        raise InputError(f"{where}: {value_m:g} m is beyond {MAX_POSITION_M / 1000:g} km of the "
                         f"origin")


def check_time(value_s: float, where: str) -> None:
    """Refuse a time beyond `MAX_TIME_S` (either side of zero)."""
    if not abs(value_s) <= MAX_TIME_S:
        raise InputError(f"{where}: {value_s:g} s is beyond 100 years")
