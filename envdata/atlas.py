"""An area's ``[atlas]``: the observer positions and months an atlas holds tables for.

README "Atlases" and docs/formats.md "Atlas (Zarr store)". Positions are either a lattice over a
box (rows every ``spacing_km`` northward from the box's south edge, columns every ``spacing_km``
eastward from its west edge, km converted to degrees with the WGS84 radii of curvature at the
box's centre latitude; the nodes inside the box) or listed ``[lat, lon]`` pairs. Months are those
of a 12-month climatology (default: the area's ``[water] month``, else month 0, "the data files'
own water"). ``depth_step_m`` or ``depth_m`` give the atlas its own TL depth axis (BELLHOP's
cost grows with the receivers); without them each table keeps the ``[grid] depth_step_m`` axis.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from envdata.errors import AreaError

#: Most observer positions an atlas may have (each one a table per month).
MAX_POSITIONS = 100_000
#: WGS84 semi-major axis, m, and first eccentricity squared.
WGS84_A_M = 6_378_137.0
WGS84_E2 = 6.694379990141317e-3
#: A node on the box's edge counts as inside within this fraction of a spacing.
EDGE_TOLERANCE = 1e-9


def metres_per_degree(lat_deg: float) -> tuple[float, float]:
    """Metres per degree of latitude and of longitude at a latitude (WGS84 radii of curvature)."""
    phi = math.radians(lat_deg)
    w = 1.0 - WGS84_E2 * math.sin(phi) ** 2
    meridional_m = WGS84_A_M * (1.0 - WGS84_E2) / w ** 1.5
    normal_m = WGS84_A_M / math.sqrt(w)
    return meridional_m * math.pi / 180.0, normal_m * math.cos(phi) * math.pi / 180.0


@dataclass(frozen=True, slots=True, kw_only=True)
class AtlasSpec:
    """The ``[atlas]`` table: a lattice over a box, or listed positions; months; a depth axis.

    Attributes
    ----------
    lat_deg, lon_deg : (float, float) or None
        The lattice's box, WGS84: south and north, west and east edges, deg.
    spacing_km : float or None
        Lattice spacing, east-west and north-south, km.
    positions : tuple of (lat_deg, lon_deg) or None
        Listed positions, deg (instead of a lattice).
    months : tuple of int or None
        Months 1..12 of a 12-month climatology; None: the area's month.
    depth_step_m : float or None
        The atlas's TL depth axis: 0, step, 2 step, ... down to each table's deepest bottom, m.
    depth_m : tuple of float or None
        Or listed TL depths, m, increasing from >= 0.
    """

    lat_deg: tuple[float, float] | None = None
    lon_deg: tuple[float, float] | None = None
    spacing_km: float | None = None
    positions: tuple[tuple[float, float], ...] | None = None
    months: tuple[int, ...] | None = None
    depth_step_m: float | None = None
    depth_m: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        lattice = (self.lat_deg, self.lon_deg, self.spacing_km)
        if self.positions is None:
            if any(v is None for v in lattice):
                raise AreaError("[atlas]: give a lattice (lat_deg, lon_deg and spacing_km) or positions")
            self._check_lattice()
        else:
            if any(v is not None for v in lattice):
                raise AreaError("[atlas]: give either a lattice (lat_deg, lon_deg, spacing_km) or positions, "
                                "not both")
            self._check_positions()
        if self.months is not None:
            if not self.months:
                raise AreaError("[atlas] months: need at least one month")
            for m in self.months:
                if isinstance(m, bool) or not isinstance(m, int) or not 1 <= m <= 12:
                    raise AreaError(f"[atlas] months: each month must be an integer in 1..12, got {m!r}")
            if len(set(self.months)) != len(self.months) or list(self.months) != sorted(self.months):
                raise AreaError(f"[atlas] months: must increase without repeats, got {list(self.months)}")
        if self.depth_step_m is not None and self.depth_m is not None:
            raise AreaError("[atlas]: give depth_step_m or depth_m, not both")
        if self.depth_step_m is not None and not (math.isfinite(self.depth_step_m)
                                                  and 0.0 < self.depth_step_m <= 12000.0):
            raise AreaError(f"[atlas] depth_step_m: must be in (0, 12000] m, got {self.depth_step_m}")
        if self.depth_m is not None:
            z = self.depth_m
            if not z or not all(math.isfinite(v) and 0.0 <= v <= 12000.0 for v in z):
                raise AreaError(f"[atlas] depth_m: need depths in [0, 12000] m, got {list(z)}")
            if any(b <= a for a, b in zip(z, z[1:])):
                raise AreaError(f"[atlas] depth_m: depths must increase, got {list(z)}")

    def _check_lattice(self) -> None:
        for key, pair, lo, hi in (("lat_deg", self.lat_deg, -89.0, 89.0), ("lon_deg", self.lon_deg, -180.0, 360.0)):
            if len(pair) != 2:
                raise AreaError(f"[atlas] {key}: need two edges, got {list(pair)}")
            a, b = pair
            if not (lo <= a < b <= hi):
                raise AreaError(f"[atlas] {key}: need {lo:g} <= first < second <= {hi:g} deg, got {a}, {b}")
        if not (math.isfinite(self.spacing_km) and 0.01 <= self.spacing_km <= 1000.0):
            raise AreaError(f"[atlas] spacing_km: must be in [0.01, 1000] km, got {self.spacing_km}")
        rows, cols = self.lattice_shape
        if rows * cols > MAX_POSITIONS:
            raise AreaError(f"[atlas] spacing_km: {self.spacing_km:g} km over the box gives {rows} x {cols} = "
                            f"{rows * cols} positions, more than {MAX_POSITIONS}")

    def _check_positions(self) -> None:
        if not self.positions:
            raise AreaError("[atlas] positions: need at least one [lat, lon] position")
        if len(self.positions) > MAX_POSITIONS:
            raise AreaError(f"[atlas] positions: {len(self.positions)} positions, more than {MAX_POSITIONS}")
        seen = set()
        for p in self.positions:
            if len(p) != 2 or not (-89.0 <= p[0] <= 89.0 and -180.0 <= p[1] <= 360.0):
                raise AreaError(f"[atlas] positions: each must be [lat_deg, lon_deg] within [-89, 89] and "
                                f"[-180, 360] deg, got {list(p)}")
            if tuple(p) in seen:
                raise AreaError(f"[atlas] positions: duplicate position {list(p)}")
            seen.add(tuple(p))

    @property
    def is_lattice(self) -> bool:
        return self.positions is None

    @property
    def step_deg(self) -> tuple[float, float]:
        """The lattice's spacing in latitude and longitude, deg (at the box's centre latitude)."""
        per_lat_m, per_lon_m = metres_per_degree(0.5 * (self.lat_deg[0] + self.lat_deg[1]))
        return 1000.0 * self.spacing_km / per_lat_m, 1000.0 * self.spacing_km / per_lon_m

    @property
    def lattice_shape(self) -> tuple[int, int]:
        """Rows (south to north) and columns (west to east) of the lattice."""
        dlat, dlon = self.step_deg
        rows = int(math.floor((self.lat_deg[1] - self.lat_deg[0]) / dlat + EDGE_TOLERANCE)) + 1
        cols = int(math.floor((self.lon_deg[1] - self.lon_deg[0]) / dlon + EDGE_TOLERANCE)) + 1
        return rows, cols

    def all_positions(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Every position before screening: lat, lon (deg) and, for a lattice, (row, col) of
        each (shape (P, 2); -1 for listed positions). Row-major, south-west first."""
        if self.positions is not None:
            lat = np.array([p[0] for p in self.positions], dtype=float)
            lon = np.array([p[1] for p in self.positions], dtype=float)
            return lat, lon, np.full((lat.size, 2), -1, dtype=np.int64)
        rows, cols = self.lattice_shape
        dlat, dlon = self.step_deg
        r, c = np.meshgrid(np.arange(rows), np.arange(cols), indexing="ij")
        lat = self.lat_deg[0] + r.ravel() * dlat
        lon = self.lon_deg[0] + c.ravel() * dlon
        return lat, lon, np.stack([r.ravel(), c.ravel()], axis=1).astype(np.int64)

    def to_dict(self) -> dict[str, object]:
        """The ``[atlas]`` table as it was given."""
        out: dict[str, object] = {}
        if self.positions is not None:
            out["positions"] = [list(p) for p in self.positions]
        else:
            out.update({"lat_deg": list(self.lat_deg), "lon_deg": list(self.lon_deg),
                        "spacing_km": self.spacing_km})
        if self.months is not None:
            out["months"] = list(self.months)
        if self.depth_step_m is not None:
            out["depth_step_m"] = self.depth_step_m
        if self.depth_m is not None:
            out["depth_m"] = list(self.depth_m)
        return out
