"""Changes to the data an area reads: a perturbed relief, water masses, a displaced front, a month.

A sensitivity study of an area with an ``[origin]`` perturbs what its radials are cut from, not
the files: ``envdata.radials.area_radials(area, change=FieldChange(...))`` applies the change to
the bathymetry box and the temperature/salinity box it has just read, before the radials are
sampled. A `FieldChange` holds everything one member drew (smooth random fields as sums of random
Fourier modes, a displacement, a month weight), so it is evaluated at any position and is the
same whoever evaluates it; a `FieldChange` of zero amplitudes gives exactly the radials of the
unchanged area.

- relief: a smooth Gaussian random field f (unit variance, covariance exp(-d^2 / 2 L^2), L the
  correlation length) changes the water depth of each sea cell, ``D' = D exp(sd_frac f) +
  sd_m f`` (log-normal in the fraction: never land), at least `MIN_SEA_DEPTH_M`; land cells and
  cells with no value stay as they are.
- water: T' = T + a_T sd_T(z, lat, lon) f_T(x, y, z), likewise S, f_T and f_S independent smooth
  fields correlated over ``scale_m`` in depth and L horizontally; sd_T the climatology's own
  ``t_sd`` (``TsField.temperature_sd_c``) unless a value is given; T and S kept in the sea's
  range (``envdata.climatology``).
- front: the whole T/S field displaced horizontally by (east, north) metres: the water found at
  a position is the climatology's at the position less the displacement.
- month: T and S (and their sds) the weighted mean of the area's month and another one of a
  12-month climatology.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from envdata.climatology import SALINITY_RANGE, TEMPERATURE_RANGE_C, TsField
from envdata.errors import AreaError

#: Modes of each random field: a sum of this many random cosines is close to Gaussian.
N_MODES = 64
#: A sea cell of a changed relief keeps at least this much water, m (it never turns into land).
MIN_SEA_DEPTH_M = 1.0
#: Metres per degree of latitude (the fields' local plane; the areas span tens of km), m.
M_PER_DEG_LAT = 111_132.0


@dataclass(frozen=True, eq=False, kw_only=True)
class SmoothField:
    """A Gaussian random field of unit variance as a sum of random Fourier modes.

    f(x) = sqrt(2 / N) sum_i cos(k_i . x + phi_i), k_i ~ N(0, I / L^2) (per axis its own L),
    phi_i ~ U(0, 2 pi): the covariance is exp(-sum_a d_a^2 / 2 L_a^2).

    Attributes
    ----------
    wavenumber_per_m : ndarray, shape (N, A)
        k_i, rad/m, one column per axis (east, north[, depth]).
    phase_rad : ndarray, shape (N,)
    """

    wavenumber_per_m: np.ndarray
    phase_rad: np.ndarray

    @classmethod
    def draw(cls, rng: np.random.Generator, scales_m: tuple[float, ...]) -> "SmoothField":
        """A field with correlation lengths ``scales_m`` (one per axis, m) from ``rng``."""
        k = rng.standard_normal((N_MODES, len(scales_m))) / np.asarray(scales_m, dtype=float)
        return cls(wavenumber_per_m=k, phase_rad=rng.uniform(0.0, 2.0 * math.pi, N_MODES))

    def __call__(self, *coords_m) -> np.ndarray:
        """f at points; ``coords_m`` one array per axis (broadcast together), m."""
        coords = np.broadcast_arrays(*(np.asarray(c, dtype=float) for c in coords_m))
        arg = sum(c[..., None] * self.wavenumber_per_m[:, a] for a, c in enumerate(coords))
        return math.sqrt(2.0 / N_MODES) * np.cos(arg + self.phase_rad).sum(axis=-1)


@dataclass(frozen=True, eq=False, kw_only=True)
class ReliefChange:
    """D' = D exp(sd_frac f) + sd_m f on sea cells (see the module)."""

    field: SmoothField
    sd_m: float = 0.0
    sd_frac: float = 0.0


@dataclass(frozen=True, eq=False, kw_only=True)
class WaterChange:
    """T and S changed by smooth fields scaled by their sds (see the module).

    ``sd_c`` / ``sd_psu``: the sd to use, degC / practical salinity; None: the climatology's own
    (``t_sd`` / ``s_sd``); ``factor`` multiplies either.
    """

    temperature_field: SmoothField
    salinity_field: SmoothField
    sd_c: float | None = None
    sd_psu: float | None = None
    factor: float = 1.0


@dataclass(frozen=True, eq=False, kw_only=True)
class FieldChange:
    """What one member changes in the data an area reads (all optional; None: unchanged).

    Attributes
    ----------
    origin_lat_deg, origin_lon_deg : float
        Origin of the local plane the random fields live on (the area's origin), deg.
    relief : ReliefChange or None
    water : WaterChange or None
    front_east_m, front_north_m : float
        Displacement of the whole T/S field, m.
    other_month : int or None
        A month of the climatology to mix in (1..12) with weight ``month_weight`` in [0, 1].
    """

    origin_lat_deg: float
    origin_lon_deg: float
    relief: ReliefChange | None = None
    water: WaterChange | None = None
    front_east_m: float = 0.0
    front_north_m: float = 0.0
    other_month: int | None = None
    month_weight: float = 0.0

    def local_m(self, lat_deg, lon_deg) -> tuple[np.ndarray, np.ndarray]:
        """Positions on the local plane about the origin: (east, north), m (equirectangular)."""
        lat = np.asarray(lat_deg, dtype=float)
        lon = np.asarray(lon_deg, dtype=float)
        dlon = (lon - self.origin_lon_deg + 180.0) % 360.0 - 180.0
        east = dlon * M_PER_DEG_LAT * math.cos(math.radians(self.origin_lat_deg))
        return east, (lat - self.origin_lat_deg) * M_PER_DEG_LAT

    def water_positions(self, lat_deg, lon_deg) -> tuple[np.ndarray, np.ndarray]:
        """Where the climatology is read for water found at (lat, lon): less the front's displacement."""
        lat = np.asarray(lat_deg, dtype=float)
        lon = np.asarray(lon_deg, dtype=float)
        if self.front_east_m == 0.0 and self.front_north_m == 0.0:
            return lat, lon
        new_lat = lat - self.front_north_m / M_PER_DEG_LAT
        new_lon = lon - self.front_east_m / (M_PER_DEG_LAT * np.cos(np.radians(lat)))
        return new_lat, new_lon

    def change_relief(self, lat_deg: np.ndarray, lon_deg: np.ndarray, elevation_m: np.ndarray) -> np.ndarray:
        """The elevation of a box (ny, nx) on axes ``lat_deg`` (ny,), ``lon_deg`` (nx,), m, positive up."""
        if self.relief is None:
            return elevation_m
        rel = self.relief
        east, north = self.local_m(lat_deg[:, None], lon_deg[None, :])
        f = rel.field(east, north)
        sea = np.isfinite(elevation_m) & (elevation_m < 0.0)
        depth = -elevation_m
        new_depth = np.maximum(depth * np.exp(rel.sd_frac * f) + rel.sd_m * f, MIN_SEA_DEPTH_M)
        return np.where(sea, -new_depth, elevation_m)

    def change_water(self, ts: TsField) -> TsField:
        """The T/S box with the water change applied (T and S kept in the sea's range)."""
        if self.water is None:
            return ts
        w = self.water
        east, north = self.local_m(ts.lat_deg[None, :, None], ts.lon_deg[None, None, :])
        z = ts.depth_m[:, None, None]
        out = {}
        for name, sd_name, given, field, (lo, hi), what in (
                ("temperature_c", "temperature_sd_c", w.sd_c, w.temperature_field, TEMPERATURE_RANGE_C,
                 "t_sd"),
                ("salinity_psu", "salinity_sd_psu", w.sd_psu, w.salinity_field, SALINITY_RANGE, "s_sd")):
            values = getattr(ts, name)
            if given is not None:
                sd = np.full(values.shape, float(given))
            else:
                own = getattr(ts, sd_name)
                if own is None:
                    raise AreaError(f"{ts.path}: the climatology has no {what} to perturb the water with; "
                                    f"give the sd")
                sd = np.nan_to_num(own, nan=0.0)
            change = w.factor * sd * field(east, north, z)
            out[name] = np.where(np.isfinite(values), np.clip(values + change, lo, hi), values)
        return dataclasses.replace(ts, **out)


def blend_months(a: TsField, b: TsField, weight_b: float) -> TsField:
    """(1 - w) a + w b of two months' boxes of one climatology (T, S and their sds)."""
    def mix(x, y):
        if x is None or y is None:
            return None
        return (1.0 - weight_b) * x + weight_b * y

    return dataclasses.replace(a, temperature_c=mix(a.temperature_c, b.temperature_c),
                               salinity_psu=mix(a.salinity_psu, b.salinity_psu),
                               temperature_sd_c=mix(a.temperature_sd_c, b.temperature_sd_c),
                               salinity_sd_psu=mix(a.salinity_sd_psu, b.salinity_sd_psu))
