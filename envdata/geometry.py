"""Where a range- and bearing-dependent area is computed: its origin and the bearings of its radials.

docs/formats.md "[origin] and [bearings]": the area is described around an
origin (WGS84 latitude and longitude, the point where the observer operates) and computed along
radials from it, one per bearing, clockwise from true north.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

from envdata.errors import AreaError

#: Most radials an area may have (each one is a BELLHOP run per class and band); 0.5 deg steps.
MAX_BEARINGS = 720


@dataclass(frozen=True, slots=True, kw_only=True)
class Origin:
    """The origin of the radials, WGS84 geodetic latitude and longitude, deg."""

    lat_deg: float
    lon_deg: float

    def __post_init__(self) -> None:
        if not (math.isfinite(self.lat_deg) and -90.0 < self.lat_deg < 90.0):
            raise AreaError(f"[origin] lat_deg: must be in (-90, 90) deg (a bearing has no meaning at "
                            f"a pole), got {self.lat_deg}")
        if not (math.isfinite(self.lon_deg) and -180.0 <= self.lon_deg <= 360.0):
            raise AreaError(f"[origin] lon_deg: must be in [-180, 360] deg, got {self.lon_deg}")


@dataclass(frozen=True, slots=True, kw_only=True)
class Bearings:
    """The radials' bearings, deg clockwise from true north at the origin.

    Given either as a step (``step_deg``: 0, step, 2 step, ... below 360, the step dividing 360)
    or as a list (``bearing_deg``, strictly increasing in [0, 360)); exactly one of the two.
    The area file is written back in the form it was given.
    """

    step_deg: float | None = None
    listed_deg: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        if (self.step_deg is None) == (self.listed_deg is None):
            raise AreaError("[bearings]: give either step_deg or bearing_deg (one of the two)")
        if self.step_deg is not None:
            step = self.step_deg
            if not (math.isfinite(step) and 0.0 < step <= 360.0):
                raise AreaError(f"[bearings] step_deg: must be in (0, 360] deg, got {step}")
            n = 360.0 / step
            if abs(n - round(n)) > 1e-9 * n:
                raise AreaError(f"[bearings] step_deg: {step} deg does not divide 360 deg into whole "
                                f"steps (360 / {step} = {n:.6g}); use a divisor of 360 such as 5, 10, 15, 30")
            if round(n) > MAX_BEARINGS:
                raise AreaError(f"[bearings] step_deg: {step} deg gives {round(n)} radials, more than "
                                f"{MAX_BEARINGS}")
        else:
            values = self.listed_deg
            if not values:
                raise AreaError("[bearings] bearing_deg: need at least one bearing")
            if len(values) > MAX_BEARINGS:
                raise AreaError(f"[bearings] bearing_deg: {len(values)} bearings, more than {MAX_BEARINGS}")
            for value in values:
                if not (math.isfinite(value) and 0.0 <= value < 360.0):
                    raise AreaError(f"[bearings] bearing_deg: each bearing must be in [0, 360) deg, "
                                    f"got {value}")
            seen = set()
            for value in values:
                if value in seen:
                    raise AreaError(f"[bearings] bearing_deg: duplicate bearing {value} deg")
                seen.add(value)
            for a, b in zip(values, values[1:]):
                if not b > a:
                    raise AreaError(f"[bearings] bearing_deg: bearings must increase, got {a} deg "
                                    f"then {b} deg")

    @property
    def bearing_deg(self) -> tuple[float, ...]:
        """The bearings in the area's order, deg clockwise from true north, in [0, 360)."""
        if self.listed_deg is not None:
            return self.listed_deg
        n = int(round(360.0 / self.step_deg))
        return tuple(float(i * self.step_deg) for i in range(n))

    def to_dict(self) -> dict[str, object]:
        """The ``[bearings]`` table as it was given."""
        if self.step_deg is not None:
            return {"step_deg": self.step_deg}
        return {"bearing_deg": list(self.listed_deg)}


def local_plane_to_lat_lon(origin_lat_deg: float, origin_lon_deg: float, x_m, y_m):
    """Latitude and longitude, deg, of points x east and y north of an origin, m, in the
    azimuthal equidistant projection centred on it (WGS84): the local plane of scenario,
    measurement, truth and track files of an area with an ``[origin]``."""
    import numpy as np

    x, y = np.broadcast_arrays(np.asarray(x_m, dtype=float), np.asarray(y_m, dtype=float))
    lon, lat = _plane(float(origin_lat_deg), float(origin_lon_deg))(*_one_as_scalar(x, y), inverse=True)
    return np.asarray(lat).reshape(x.shape), np.asarray(lon).reshape(x.shape)


def lat_lon_to_local_plane(origin_lat_deg: float, origin_lon_deg: float, lat_deg, lon_deg):
    """x east and y north of an origin, m, of points at latitudes and longitudes, deg: the inverse
    of `local_plane_to_lat_lon` (azimuthal equidistant projection centred on the origin, WGS84)."""
    import numpy as np

    lat, lon = np.broadcast_arrays(np.asarray(lat_deg, dtype=float), np.asarray(lon_deg, dtype=float))
    x, y = _plane(float(origin_lat_deg), float(origin_lon_deg))(*_one_as_scalar(lon, lat))
    return np.asarray(x).reshape(lat.shape), np.asarray(y).reshape(lat.shape)


def _one_as_scalar(*arrays):
    """The (broadcast) arrays, those of a single value as 0-d arrays (pyproj 3.7 takes a (1,) array for a
    scalar and numpy 2 warns that the conversion will fail)."""
    return tuple(a.reshape(()) if a.size == 1 else a for a in arrays)


@functools.lru_cache(maxsize=16)
def _plane(origin_lat_deg: float, origin_lon_deg: float):
    """The azimuthal equidistant projection about an origin (WGS84), made once per origin (a
    tracker converts a position every cycle)."""
    from pyproj import Proj

    return Proj(proj="aeqd", lat_0=origin_lat_deg, lon_0=origin_lon_deg, ellps="WGS84")
