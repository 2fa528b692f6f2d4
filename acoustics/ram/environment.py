"""One 2-D (range-dependent) RAM problem: bathymetry, sound-speed section, bottom, source.

RAM marches outward from the source at range 0, so a ``RamEnvironment`` holds only ranges
>= 0: a radial's part behind the origin, which BELLHOP's rays can reach, is dropped. The
sound-speed section is ``speed_mps[range, depth]`` (range points x depth points), the
transpose of ``envdata.radials.Radial.speed_mps`` and of easypyram's ``cw`` (depth x range):
``acoustics.ram.run`` is the one place that turns it for easypyram.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from acoustics.ram.errors import RamInputError
from envdata.area import Absorption, Area
from envdata.bottom import Bottom
from envdata.radials import Radial

#: Sound speeds a RAM environment may hold, m/s (as envdata's profiles).
MIN_SPEED_MPS, MAX_SPEED_MPS = 1300.0, 1800.0


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class RamEnvironment:
    """The environment of one RAM run: a vertical plane from the source outward.

    Attributes
    ----------
    bathymetry_range_m : ndarray, shape (B,)
        Ranges of the bottom points, m, increasing, the first 0. RAM interpolates the bottom
        linearly between them and holds the last depth beyond the last point.
    bathymetry_depth_m : ndarray, shape (B,)
        Water depth at those ranges, m, positive down, > 0.
    ssp_range_m : ndarray, shape (P,)
        Ranges of the sound-speed columns, m, increasing, the first 0.
    ssp_depth_m : ndarray, shape (Z,)
        Depths of the section, m, increasing from 0 to at least the deepest bottom point.
    speed_mps : ndarray, shape (P, Z)
        Sound speed in the water, m/s: one row per range point, one column per depth point.
    bottom : envdata.bottom.Bottom
        The fluid half-space under the water everywhere (speed, density, attenuation in
        dB/wavelength). RAM has no shear: a bottom with ``shear_speed_mps > 0`` is refused.
    source_depth_m : float
        Source depth at range 0, m; in the water there.
    end_range_m : float or None
        Where the problem ends, m (a radial's end, or where it meets land); None: no end (a flat
        area). TL is NaN beyond it.
    absorption : envdata.area.Absorption
        Volume absorption in the water (``acoustics.absorption``), added to RAM's TL as
        alpha(f) r: RAM itself has none.
    """

    bathymetry_range_m: np.ndarray
    bathymetry_depth_m: np.ndarray
    ssp_range_m: np.ndarray
    ssp_depth_m: np.ndarray
    speed_mps: np.ndarray
    bottom: Bottom
    source_depth_m: float
    end_range_m: float | None = None
    absorption: Absorption = Absorption.NONE

    def __post_init__(self) -> None:
        for name in ("bathymetry_range_m", "bathymetry_depth_m", "ssp_range_m", "ssp_depth_m", "speed_mps"):
            value = np.array(getattr(self, name), dtype=float)
            if not np.all(np.isfinite(value)):
                raise RamInputError(f"RAM environment {name}: values must be finite (no NaN)")
            value.setflags(write=False)  # frozen all the way down
            object.__setattr__(self, name, value)
        _check_axis("bathymetry_range_m", self.bathymetry_range_m)
        _check_axis("ssp_range_m", self.ssp_range_m)
        rb, zb = self.bathymetry_range_m, self.bathymetry_depth_m
        if zb.shape != rb.shape:
            raise RamInputError(f"RAM environment bathymetry_depth_m: {zb.size} depths for {rb.size} ranges")
        if np.any(zb <= 0.0):
            raise RamInputError(f"RAM environment bathymetry_depth_m: water depth must be > 0 m, "
                                f"got {float(zb.min())} m")
        z = self.ssp_depth_m
        if z.ndim != 1 or z.size < 2 or z[0] != 0.0 or np.any(np.diff(z) <= 0.0):
            raise RamInputError("RAM environment ssp_depth_m: need at least 2 depths increasing "
                                f"strictly from 0 m, got {z.tolist()[:5]}")
        if z[-1] < zb.max() - 1e-6:
            raise RamInputError(f"RAM environment ssp_depth_m: ends at {z[-1]} m, above the deepest "
                                f"bottom point, {float(zb.max())} m")
        c = self.speed_mps
        if c.shape != (self.ssp_range_m.size, z.size):
            raise RamInputError(f"RAM environment speed_mps: shape {c.shape} is not (range points, depth "
                                f"points) = ({self.ssp_range_m.size}, {z.size})")
        if c.min() < MIN_SPEED_MPS or c.max() > MAX_SPEED_MPS:
            raise RamInputError(f"RAM environment speed_mps: speeds must be in [{MIN_SPEED_MPS:g}, "
                                f"{MAX_SPEED_MPS:g}] m/s, got {float(c.min())} to {float(c.max())} m/s")
        if self.bottom.shear_speed_mps > 0.0:
            raise RamInputError(f"RAM environment bottom: RAM's bottom is a fluid, got shear_speed_mps "
                                f"{self.bottom.shear_speed_mps} m/s (BELLHOP takes shear; RAM does not)")
        zs = float(self.source_depth_m)
        if not (math.isfinite(zs) and 0.0 < zs < zb[0]):
            raise RamInputError(f"RAM environment source_depth_m: must be in (0, {float(zb[0])}) m, the "
                                f"water at range 0, got {self.source_depth_m} m")
        if self.end_range_m is not None and not (math.isfinite(self.end_range_m) and self.end_range_m > 0.0):
            raise RamInputError(f"RAM environment end_range_m: must be > 0 m or None, got {self.end_range_m}")
        object.__setattr__(self, "absorption", Absorption(self.absorption))

    @classmethod
    def from_area(cls, area: Area, source_depth_m: float) -> RamEnvironment:
        """The problem of a flat area: its water depth, its one profile and its bottom.

        Parameters
        ----------
        area : envdata.Area
            An area with a flat bottom (``[water] depth_m``) and one sound-speed profile, as
            ``acoustics.bellhop.envfile.env_text`` reads it. Its ``[propagation] absorption``
            is the volume absorption.
        source_depth_m : float
            Source depth, m (0 < depth < the water depth).

        Raises
        ------
        RamInputError
            The area's bottom comes from a bathymetry file (use `from_radial`), or the source
            is not in the water.
        """
        water = area.water
        if not water.is_flat or water.ssp is None:
            raise RamInputError(f"area {area.name!r}: RamEnvironment.from_area needs a flat bottom and one "
                                f"sound-speed profile; an area with bathymetry or a climatology is "
                                f"computed along its radials (RamEnvironment.from_radial)")
        ssp_z = np.asarray(water.ssp.depth_m, dtype=float)
        ssp_c = np.asarray(water.ssp.speed_mps, dtype=float)
        return cls(bathymetry_range_m=np.array([0.0]), bathymetry_depth_m=np.array([float(water.depth_m)]),
                   ssp_range_m=np.array([0.0]), ssp_depth_m=ssp_z, speed_mps=ssp_c[None, :],
                   bottom=area.bottom, source_depth_m=float(source_depth_m), end_range_m=None,
                   absorption=area.propagation.absorption)

    @classmethod
    def from_radial(cls, area: Area, radial: Radial, source_depth_m: float) -> RamEnvironment:
        """The problem along one radial of a range-dependent area, from its origin outward.

        Parameters
        ----------
        area : envdata.Area
            The radial's area: its bottom half-space and volume absorption.
        radial : envdata.radials.Radial
            Bottom depth and sound-speed section along the radial (``envdata.area_radials``).
            Its ranges behind the origin (< 0) are dropped; the bottom and the sound speed at
            range 0 are interpolated linearly between the samples on either side.
        source_depth_m : float
            Source depth at the origin, m (the observer's depth, by reciprocity, as in
            ``acoustics.radialgrid``).

        Notes
        -----
        A radial that meets land ends there (``land_range_m``): the environment's
        ``end_range_m`` is the land range, or else the radial's last range, and TL beyond it is
        NaN, as in the bearing-dependent BELLHOP grid.
        """
        r = np.asarray(radial.range_m, dtype=float)
        zb = np.asarray(radial.bottom_depth_m, dtype=float)
        if r[-1] <= 0.0:
            raise RamInputError(f"radial at bearing {radial.bearing_deg:g} deg: ends at {r[-1]} m, at or "
                                f"behind the origin; RAM needs water ahead of it")
        ahead = r > 0.0
        bathy_r = np.concatenate([[0.0], r[ahead]])
        bathy_z = np.concatenate([[float(np.interp(0.0, r, zb))], zb[ahead]])
        pr = np.asarray(radial.ssp_range_m, dtype=float)
        section = np.asarray(radial.speed_mps, dtype=float)  # (depth, range): the Radial's layout
        ahead_p = pr > 0.0
        at_origin = np.array([np.interp(0.0, pr, row) for row in section])
        speed = np.concatenate([at_origin[None, :], section[:, ahead_p].T], axis=0)  # (range, depth)
        ssp_r = np.concatenate([[0.0], pr[ahead_p]])
        end = radial.land_range_m if radial.land_range_m is not None else float(r[-1])
        return cls(bathymetry_range_m=bathy_r, bathymetry_depth_m=bathy_z, ssp_range_m=ssp_r,
                   ssp_depth_m=np.asarray(radial.ssp_depth_m, dtype=float), speed_mps=speed,
                   bottom=area.bottom, source_depth_m=float(source_depth_m), end_range_m=float(end),
                   absorption=area.propagation.absorption)

    @property
    def max_bottom_depth_m(self) -> float:
        """The deepest bottom point, m."""
        return float(self.bathymetry_depth_m.max())

    @property
    def is_range_dependent(self) -> bool:
        """True when the bottom depth or the sound speed changes with range."""
        return bool(np.ptp(self.bathymetry_depth_m) > 0.0 or np.ptp(self.speed_mps, axis=0).max() > 0.0)

    def bottom_depth_m(self, range_m) -> np.ndarray:
        """Water depth at ``range_m``, m: linear between the bottom points, the last held."""
        return np.interp(np.asarray(range_m, dtype=float), self.bathymetry_range_m, self.bathymetry_depth_m)

    def speed_at_mps(self, range_m: float) -> np.ndarray:
        """The sound-speed column at ``range_m`` on ``ssp_depth_m``, m/s: linear between columns."""
        return np.array([np.interp(range_m, self.ssp_range_m, col) for col in self.speed_mps.T])


def _check_axis(name: str, values: np.ndarray) -> None:
    if values.ndim != 1 or values.size < 1 or values[0] != 0.0 or np.any(np.diff(values) <= 0.0):
        raise RamInputError(f"RAM environment {name}: need ranges increasing strictly from 0 m, "
                            f"got {values.tolist()[:5]}")
