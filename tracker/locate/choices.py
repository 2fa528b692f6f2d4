"""The choices of the location methods (Schmidt et al.), in a module of their own so that the
command line lists them without importing numpy: how a fix is computed, how a route is steered,
and the conditioning number a fix may have."""

from __future__ import annotations

from enum import StrEnum

#: Largest conditioning number u (eq. 11) accepted for a fix; u = 1000 means bearing lines
#: about 0.11 deg apart. Above it the fix is reported as ill-conditioned instead of computed.
DEFAULT_MAX_U = 1000.0


class FixMethod(StrEnum):
    """How a position is estimated from the bearings."""

    CROSSING = "crossing"  # the last two bearings, eqs. 6-8
    LSQ = "lsq"            # least squares over all n equations (4)
    MEAN = "mean"          # mean of the fixes of consecutive pairs, eq. 29


class CourseRule(StrEnum):
    """How the observer's course is chosen for the next leg."""

    EQ17 = "eq17"  # perpendicular to the current bearing
    EQ23 = "eq23"  # perpendicular to the anticipated next bearing (modified algorithm)


class Side(StrEnum):
    """Which side of the observer the target is kept on while steering."""

    PORT = "port"            # course = bearing + 90 deg; bearings decrease (the paper's eq. 23)
    STARBOARD = "starboard"  # course = bearing - 90 deg; bearings increase

    @property
    def sign(self) -> float:
        return 1.0 if self is Side.PORT else -1.0
