"""Transmission loss and band level read from a grid by linear interpolation (eq. 13).

Iglesis & de Montella interpolate the BELLHOP TL array linearly between its points (sec. 3.2,
eq. 13). Here the array is the grid's ``tl_db(class, band, depth, range)``: TL between a source
at the class's depth and a receiver at ``depth``, horizontal distance ``range``. The band level
of a source with spectral level SL at the band's reference frequency is

    W = SL + K(depth, r),    K(depth, r) = S - TL(depth, r),

with S the band's spectral term (0 dB for a single-frequency band with the Ross model; DESIGN.md
"Grid dataset"), recovered from the grid as ``k_db + TL(observer depth)``.

Outside the range axis `TlTable.tl_at` holds the end values. The filter's `LevelProfile` holds
the first value below the axis, and beyond the last range gives K a penalty of
`BEYOND_GRID_PENALTY_DB`: the grid's range axis is the horizon of the level model, and a
particle beyond it keeps a weight only if every particle is beyond it. (Holding the end value,
or continuing it by spherical spreading, lets a fast, receding target far outside the grid
explain a steady level as well as the true one: the non-maneuvering scenario then drifts out.)
A receiver depth outside the depth axis is an error.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from acoustics.errors import GridFileError

#: K beyond the grid's last range: its last value less this, dB (a rejection, not physics).
BEYOND_GRID_PENALTY_DB = 1000.0


@dataclass(frozen=True, slots=True, kw_only=True)
class TlTable:
    """TL of one class and band on the grid's depth x range axes.

    Attributes
    ----------
    cls_name, band : str
        Class hypothesis and band names in the grid.
    depth_m : ndarray, shape (n_depth,)
        Receiver depths, m, increasing.
    range_m : ndarray, shape (n_range,)
        Horizontal ranges, m, increasing.
    tl_db : ndarray, shape (n_depth, n_range)
        Transmission loss, dB.
    spectral_db : float
        Spectral term S of the band, dB: K = S - TL (0 dB for one frequency and the Ross model).
    source_depth_m : float
        Radiating depth of the class, m.
    source_level_model : str
        "ross" (SL(v) of eq. 12) or "p0" (``noise_mean_db``).
    noise_mean_db, noise_sd_db : float
        The class's level P0 and its sd, dB re 1 uPa (model "p0"; NaN and 0 for "ross").
    source : str
        The grid's name for messages.
    """

    cls_name: str
    band: str
    depth_m: np.ndarray
    range_m: np.ndarray
    tl_db: np.ndarray
    spectral_db: float
    source_depth_m: float
    source_level_model: str = "ross"
    noise_mean_db: float = math.nan
    noise_sd_db: float = 0.0
    source: str = "<grid>"

    def check_depth(self, depth_m) -> None:
        """Raise GridFileError if a receiver depth lies outside the grid's depth axis."""
        d = np.asarray(depth_m, dtype=float)
        lo, hi = float(self.depth_m[0]), float(self.depth_m[-1])
        bad = ~((d >= lo) & (d <= hi))
        if np.any(bad):
            value = float(d[bad].flat[0])
            raise GridFileError(f"{self.source}: receiver depth {value:g} m is outside the grid's "
                                f"depth axis [{lo:g}, {hi:g}] m (class {self.cls_name!r}, band "
                                f"{self.band!r})")

    def profile_db(self, depth_m: float) -> np.ndarray:
        """TL along the range axis at one receiver depth, linear in depth (eq. 13), dB."""
        self.check_depth(depth_m)
        z = self.depth_m
        if z.size == 1:
            return self.tl_db[0].astype(float)
        j = int(np.clip(np.searchsorted(z, depth_m, side="right") - 1, 0, z.size - 2))
        f = (float(depth_m) - z[j]) / (z[j + 1] - z[j])
        return (1.0 - f) * self.tl_db[j].astype(float) + f * self.tl_db[j + 1].astype(float)

    def tl_at(self, depth_m, range_m) -> np.ndarray:
        """TL at receiver depths and ranges, bilinear in depth and range (eq. 13), dB.

        Parameters
        ----------
        depth_m, range_m : array_like
            Receiver depth and horizontal range, m (broadcast together).

        Returns
        -------
        tl_db : ndarray
            TL, dB; ranges outside the axis take the end values.
        """
        d, r = np.broadcast_arrays(np.asarray(depth_m, dtype=float),
                                   np.asarray(range_m, dtype=float))
        self.check_depth(d)
        z, x = self.depth_m, self.range_m
        if z.size == 1:
            return np.interp(r, x, self.tl_db[0])
        j = np.clip(np.searchsorted(z, d, side="right") - 1, 0, z.size - 2)
        fz = (d - z[j]) / (z[j + 1] - z[j])
        rc = np.clip(r, x[0], x[-1])
        i = np.clip(np.searchsorted(x, rc, side="right") - 1, 0, x.size - 2)
        fr = (rc - x[i]) / (x[i + 1] - x[i])
        t = self.tl_db
        low = (1.0 - fr) * t[j, i] + fr * t[j, i + 1]
        high = (1.0 - fr) * t[j + 1, i] + fr * t[j + 1, i + 1]
        return (1.0 - fz) * low + fz * high

    def level_profile(self, depth_m: float) -> "LevelProfile":
        """The band-level term K(r) = S - TL(depth, r) at one receiver depth, ready to evaluate."""
        return LevelProfile(range_m=self.range_m, k_db=self.spectral_db - self.profile_db(depth_m))


@dataclass(frozen=True, slots=True, kw_only=True)
class LevelProfile:
    """K(r) at one receiver depth: band level W = SL + K(r); linear in range."""

    range_m: np.ndarray
    k_db: np.ndarray

    def __call__(self, range_m) -> np.ndarray:
        """K at the given ranges, dB: linear inside the axis, the first value below it, and
        beyond the last range the last value less `BEYOND_GRID_PENALTY_DB`."""
        r = np.asarray(range_m, dtype=float)
        k = np.interp(r, self.range_m, self.k_db)
        return np.where(r > self.range_m[-1], k - BEYOND_GRID_PENALTY_DB, k)


def tl_table(grid: xr.Dataset, cls_name: str, band: str) -> TlTable:
    """The TL table of one class and band of a grid.

    Raises
    ------
    GridFileError
        The class or band is not in the grid.
    """
    source = str(grid.attrs.get("source_file", grid.attrs.get("area", "<grid>")))
    classes = [str(c) for c in grid["class"].values]
    bands = [str(b) for b in grid["band"].values]
    if cls_name not in classes:
        raise GridFileError(f"{source}: class {cls_name!r} is not in the grid (classes: "
                            f"{', '.join(classes)})")
    if band not in bands:
        raise GridFileError(f"{source}: band {band!r} is not in the grid (bands: "
                            f"{', '.join(bands)})")
    sel = {"class": cls_name, "band": band}
    tl = np.asarray(grid["tl_db"].sel(sel).transpose("depth", "range").values, dtype=float)
    depth = np.asarray(grid["depth"].values, dtype=float)
    rng = np.asarray(grid["range"].values, dtype=float)
    k = np.asarray(grid["k_db"].sel(sel).values, dtype=float)
    table = TlTable(cls_name=cls_name, band=band, depth_m=depth, range_m=rng, tl_db=tl,
                    spectral_db=0.0, source_depth_m=float(grid["source_depth_m"].sel(
                        {"class": cls_name}).values), source=source)
    obs_depth = float(grid.attrs.get("observer_depth_m", math.nan))
    spectral = 0.0
    if math.isfinite(obs_depth) and depth[0] <= obs_depth <= depth[-1]:
        spectral = float(np.median(k + table.profile_db(obs_depth)))
    model, p0, p0_sd = "ross", math.nan, 0.0
    info = _class_info(grid, cls_name)
    if info:
        model = str(info.get("source_level_model") or "p0")
        p0 = float(info["noise_mean_db"]) if info.get("noise_mean_db") is not None else math.nan
        p0_sd = float(info.get("noise_sd_db") or 0.0)
    return TlTable(cls_name=cls_name, band=band, depth_m=depth, range_m=rng, tl_db=tl,
                   spectral_db=spectral, source_depth_m=table.source_depth_m,
                   source_level_model=model, noise_mean_db=p0, noise_sd_db=p0_sd, source=source)


def _class_info(grid: xr.Dataset, cls_name: str) -> dict | None:
    text = grid.attrs.get("area_json")
    if not text:
        return None
    try:
        area = json.loads(text)
    except ValueError:
        return None
    for cls in area.get("classes", []):
        if cls.get("name") == cls_name:
            return cls
    return None
