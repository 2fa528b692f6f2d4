"""Sound-speed profiles: tables, the canonical Munk profile, and temperature/salinity via TEOS-10."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from envdata.errors import AreaError

# Canonical Munk profile (Munk 1974; Jensen, Kuperman, Porter & Schmidt, eq. 5.106).
MUNK_AXIS_M = 1300.0
MUNK_SCALE_M = 1300.0
MUNK_EPSILON = 0.00737
MUNK_AXIS_SPEED_MPS = 1500.0

# Speeds outside this range do not occur in sea water; a profile there is a unit or typing error.
MIN_SPEED_MPS = 1400.0
MAX_SPEED_MPS = 1650.0


def munk_speed_mps(depth_m):
    """Canonical Munk sound speed c(z) = c1 (1 + eps (eta - 1 + exp(-eta))), eta = 2 (z - z1) / B."""
    eta = 2.0 * (np.asarray(depth_m, dtype=float) - MUNK_AXIS_M) / MUNK_SCALE_M
    return MUNK_AXIS_SPEED_MPS * (1.0 + MUNK_EPSILON * (eta - 1.0 + np.exp(-eta)))


def speed_outside(speed_mps) -> int | None:
    """Index of the first speed outside [`MIN_SPEED_MPS`, `MAX_SPEED_MPS`], None when all are in."""
    c = np.asarray(speed_mps, dtype=float)
    bad = (c < MIN_SPEED_MPS) | (c > MAX_SPEED_MPS)
    return int(np.argmax(bad)) if np.any(bad) else None


def _check_depths_and_option(z: np.ndarray, interpolation: str, what: str) -> None:
    """A profile's depths strictly increasing and its BELLHOP SSP option one BELLHOP has."""
    if np.any(np.diff(z) <= 0):
        i = int(np.argmax(np.diff(z) <= 0))
        raise AreaError(f"{what}: depths must increase strictly, got {z[i]} m then {z[i + 1]} m")
    if interpolation not in ("C", "S", "N", "P"):
        raise AreaError(f"{what}: interpolation must be one of C, S, N, P, got {interpolation!r}")


@dataclass(frozen=True, slots=True, kw_only=True)
class SoundSpeedProfile:
    """A tabulated profile from the surface to the bottom, interpolated linearly (BELLHOP 'C')."""

    depth_m: tuple[float, ...]
    speed_mps: tuple[float, ...]
    # where the table came from: "table", "munk" or "ts" (converted from temperature and
    # salinity); provenance only, so two profiles with the same numbers are equal
    kind: str = field(default="table", compare=False)
    interpolation: str = "C"  # BELLHOP SSP option: C linear, S cubic spline, N n2-linear, P pchip

    def __post_init__(self) -> None:
        z = np.asarray(self.depth_m, dtype=float)
        c = np.asarray(self.speed_mps, dtype=float)
        if z.ndim != 1 or z.size < 2 or z.size != c.size:
            raise AreaError(f"sound-speed profile: need at least 2 depths and as many speeds, "
                            f"got {z.size} depths and {c.size} speeds")
        if not (np.all(np.isfinite(z)) and np.all(np.isfinite(c))):
            raise AreaError("sound-speed profile: depths and speeds must be finite (no NaN)")
        if z[0] != 0.0:
            raise AreaError(f"sound-speed profile: must start at the surface, 0 m, got {z[0]} m")
        _check_depths_and_option(z, self.interpolation, "sound-speed profile")
        i = speed_outside(c)
        if i is not None:
            raise AreaError(f"sound-speed profile: speed {c[i]} m/s at {z[i]} m is outside "
                            f"[{MIN_SPEED_MPS:g}, {MAX_SPEED_MPS:g}] m/s")

    @property
    def bottom_m(self) -> float:
        return self.depth_m[-1]

    def speed_at(self, depth_m):
        """Sound speed at ``depth_m`` by linear interpolation, m/s."""
        return np.interp(depth_m, self.depth_m, self.speed_mps)


def munk_profile(water_depth_m: float, step_m: float = 25.0) -> SoundSpeedProfile:
    """The canonical Munk profile sampled every ``step_m`` and cut at the water depth."""
    n = max(2, int(math.ceil(water_depth_m / step_m)) + 1)
    z = np.linspace(0.0, water_depth_m, n)
    return SoundSpeedProfile(depth_m=tuple(float(v) for v in z),
                             speed_mps=tuple(float(v) for v in np.round(munk_speed_mps(z), 3)),
                             kind="munk")


def teos10_speed_mps(depth_m, temperature_c, salinity_psu, *, latitude_deg, longitude_deg):
    """TEOS-10 sound speed from in-situ temperature and practical salinity, m/s.

    Pressure from depth at the latitude (gsw.p_from_z), Absolute Salinity from Practical
    Salinity at the position, Conservative Temperature from in-situ temperature, then the
    TEOS-10 sound speed. Arguments broadcast against each other (numpy rules), so a section of
    columns is one call: depths (Z, 1) against column latitudes (P,).
    """
    import gsw

    z = np.asarray(depth_m, dtype=float)
    p_dbar = gsw.p_from_z(-z, latitude_deg)
    sa = gsw.SA_from_SP(salinity_psu, p_dbar, longitude_deg, latitude_deg)
    ct = gsw.CT_from_t(sa, temperature_c, p_dbar)
    return np.asarray(gsw.sound_speed(sa, ct, p_dbar), dtype=float)


def check_ts(depth_m, temperature_c, salinity_psu, where: str = "sound-speed profile") -> None:
    """Refuse a T/S table that is ragged, not finite or outside the sea's range (AreaError)."""
    z = np.asarray(depth_m, dtype=float)
    t = np.asarray(temperature_c, dtype=float)
    sp = np.asarray(salinity_psu, dtype=float)
    if not (z.shape == t.shape == sp.shape):
        raise AreaError(f"{where}: ssp_depth_m, temperature_c and salinity_psu must "
                        f"have the same length, got {z.size}, {t.size}, {sp.size}")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(sp))):
        raise AreaError(f"{where}: temperature_c and salinity_psu must be finite (no NaN)")
    if np.any((t < -2.5) | (t > 40.0)):
        raise AreaError(f"{where}: temperature_c must be in [-2.5, 40] degC, "
                        f"got {t[(t < -2.5) | (t > 40.0)][0]}")
    if np.any((sp < 0.0) | (sp > 42.0)):
        raise AreaError(f"{where}: salinity_psu must be in [0, 42], "
                        f"got {sp[(sp < 0.0) | (sp > 42.0)][0]}")


def ts_profile(depth_m, temperature_c, salinity_psu, *, latitude_deg: float,
               longitude_deg: float) -> SoundSpeedProfile:
    """Profile from in-situ temperature and practical salinity, converted with TEOS-10 (gsw).

    Pressure from depth at the latitude (gsw.p_from_z), Absolute Salinity from Practical
    Salinity, Conservative Temperature from in-situ temperature, then the TEOS-10 sound speed.
    """
    z = np.asarray(depth_m, dtype=float)
    check_ts(z, temperature_c, salinity_psu)
    c = teos10_speed_mps(z, np.asarray(temperature_c, dtype=float), np.asarray(salinity_psu, dtype=float),
                         latitude_deg=latitude_deg, longitude_deg=longitude_deg)
    return SoundSpeedProfile(depth_m=tuple(float(v) for v in z),
                             speed_mps=tuple(float(v) for v in np.round(c, 3)), kind="ts")


@dataclass(frozen=True, slots=True, kw_only=True)
class TsProfile:
    """One profile of in-situ temperature and practical salinity, kept as T and S.

    The one profile of an area whose bottom comes from a bathymetry file: its depth is not
    known until the radials are sampled, so the profile is kept as T/S and converted with
    TEOS-10 at the depths each radial needs; below its deepest sample the deepest T and S
    continue (the speed then still grows with pressure). From a T/S table of the area file
    or a CTD cast (``kind``, provenance only).
    """

    depth_m: tuple[float, ...]
    temperature_c: tuple[float, ...]
    salinity_psu: tuple[float, ...]
    interpolation: str = "C"
    kind: str = field(default="ts", compare=False)

    def __post_init__(self) -> None:
        z = np.asarray(self.depth_m, dtype=float)
        if z.ndim != 1 or z.size < 2:
            raise AreaError(f"T/S profile: need at least 2 depths, got {z.size}")
        check_ts(z, self.temperature_c, self.salinity_psu, "T/S profile")
        if not np.all(np.isfinite(z)):
            raise AreaError("T/S profile: depths must be finite (no NaN)")
        if z[0] != 0.0:
            raise AreaError(f"T/S profile: must start at the surface, 0 m, got {z[0]} m")
        _check_depths_and_option(z, self.interpolation, "T/S profile")

    @property
    def bottom_m(self) -> float:
        """Depth of the deepest sample, m."""
        return self.depth_m[-1]

    def ts_at(self, depth_m) -> tuple[np.ndarray, np.ndarray]:
        """Temperature, degC, and practical salinity at ``depth_m``: linear between samples,
        the deepest sample's values below it."""
        z = np.asarray(depth_m, dtype=float)
        return (np.interp(z, self.depth_m, self.temperature_c),
                np.interp(z, self.depth_m, self.salinity_psu))

    def speed_mps(self, depth_m, *, latitude_deg: float, longitude_deg: float) -> np.ndarray:
        """TEOS-10 sound speed at ``depth_m``, m/s, pressure from depth at ``latitude_deg``."""
        t, s = self.ts_at(depth_m)
        return teos10_speed_mps(depth_m, t, s, latitude_deg=latitude_deg, longitude_deg=longitude_deg)

    def cut_at(self, water_depth_m: float) -> "TsProfile":
        """The profile from the surface to ``water_depth_m`` exactly: samples above it, then T and
        S at that depth (interpolated, or the deepest sample's continued)."""
        keep = [i for i, z in enumerate(self.depth_m) if z < water_depth_m]
        t, s = self.ts_at(water_depth_m)
        return TsProfile(depth_m=tuple(self.depth_m[i] for i in keep) + (float(water_depth_m),),
                         temperature_c=tuple(self.temperature_c[i] for i in keep) + (float(t),),
                         salinity_psu=tuple(self.salinity_psu[i] for i in keep) + (float(s),),
                         interpolation=self.interpolation, kind=self.kind)

    def to_dict(self) -> dict[str, object]:
        """The ``[water]`` keys of a T/S table."""
        return {"ssp_depth_m": list(self.depth_m), "temperature_c": list(self.temperature_c),
                "salinity_psu": list(self.salinity_psu), "ssp_interpolation": self.interpolation}
