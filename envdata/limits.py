"""Physical bounds on inputs and the memory a piece of work may take.

Positions beyond 20 000 km or times beyond 100 years are typing or unit mistakes, not sea
areas. Work whose arrays would not fit the machine (a grid, a scenario, a study, an experiment)
is refused before it starts, with the size it would take: the limit is half the machine's
memory unless a caller sets another for the work it runs (``memory_limit``: a context, not a
process-wide switch; the executor's worker threads run in their caller's context).
"""

from __future__ import annotations

import contextlib
import contextvars
import math
import os
from collections.abc import Iterator

from envdata.errors import InputError

#: Largest distance from the origin of any position, m (half the Earth's circumference).
MAX_POSITION_M = 2.0e7
#: Largest time, s (100 years).
MAX_TIME_S = 100 * 365.25 * 86400.0
GIB = 2.0 ** 30

#: The memory limit of the work under way, bytes, and who set it (None: half this machine's memory).
_LIMIT: contextvars.ContextVar[tuple[float, str] | None] = contextvars.ContextVar("tmakit_memory_limit",
                                                                                  default=None)


class TooLargeError(InputError):
    """Work that would need more memory than the limit allows."""


def machine_memory_bytes() -> float:
    """Physical memory of this machine, bytes (8 GiB when the system does not say)."""
    try:
        return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):
        return 8.0 * GIB


@contextlib.contextmanager
def memory_limit(gib: float | None, source: str = "the limit set for this work") -> Iterator[None]:
    """Run the work inside the ``with`` block under a memory limit of ``gib`` GiB (None: the
    default, half this machine's memory); ``source`` says in messages who set it."""
    if gib is not None and not (math.isfinite(gib) and gib > 0):
        raise InputError(f"{source}: must be a positive number of GiB, got {gib}")
    token = _LIMIT.set(None if gib is None else (gib * GIB, source))
    try:
        yield
    finally:
        _LIMIT.reset(token)


def memory_limit_bytes() -> tuple[float, str]:
    """The memory limit, bytes, and where it comes from (for messages)."""
    limit = _LIMIT.get()
    if limit is not None:
        return limit
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
                            f"limit of {limit / GIB:.3g} GiB ({why})")


def check_position(value_m: float, where: str) -> None:
    """Refuse a coordinate further than `MAX_POSITION_M` from the origin."""
    if not abs(value_m) <= MAX_POSITION_M:
        raise InputError(f"{where}: {value_m:g} m is beyond {MAX_POSITION_M / 1000:g} km of the "
                         f"origin")


def check_time(value_s: float, where: str) -> None:
    """Refuse a time beyond `MAX_TIME_S` (either side of zero)."""
    if not abs(value_s) <= MAX_TIME_S:
        raise InputError(f"{where}: {value_s:g} s is beyond 100 years")
