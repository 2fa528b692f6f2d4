"""How far the level a target gives scatters about its class's mean, for P_D: the one place.

P_D = Phi(SE / sigma) (``acoustics.pd``) takes sigma from here, and so do the detection ranges,
the P_D maps, the cumulative P_D along a track and the range-axis check. The level is
W = P0 + K(r) + dK + e (DESIGN.md "K's error and stated uncertainty"); what scatters it about the
class's mean splits in two:

- ``persistent_db``: what holds along a track, drawn once per target: the class's source-level
  sd (``noise_sd_db``: one target is as loud all along its track) and K's offset. Today K's error
  is one number per class and band (and, with a sensitivity study's map, per bearing and
  range): the class's ``k_error_sd_db`` or the grid's ``k_error_sd_db`` (``Tables.k_error_sd_at``).
  DESIGN.md reads an area's one ``k_error_sd_db`` as the offset, and the sensitivity study found
  K's error on the shelf break mostly a constant offset along a track, so all of it is taken
  as persistent here.
- ``per_look_db``: what is drawn anew at every look (one per integration time), independently:
  today's model has no such part (0 dB). K's residual (``k_residual_sd_db``, with its
  correlation length) belongs here once the tables carry it.

One look's P_D takes the total, sqrt(persistent^2 + per_look^2): a planner knows neither part.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from acoustics.grid.face import Tables
from envdata.errors import InputError


@dataclass(frozen=True, slots=True, kw_only=True)
class LevelSigma:
    """sd of the level about the class's mean, split by how it behaves along a track, dB.

    Attributes
    ----------
    persistent_db : ndarray
        The part drawn once per track (source level, K's offset).
    per_look_db : ndarray
        The part drawn anew at every look, independently.
    source : str
        Where the numbers came from, for a summary.
    """

    persistent_db: np.ndarray
    per_look_db: np.ndarray
    source: str

    @property
    def total_db(self) -> np.ndarray:
        """The sd of one look's level: sqrt(persistent^2 + per_look^2), dB."""
        return np.hypot(self.persistent_db, self.per_look_db)


@dataclass(frozen=True, slots=True, kw_only=True)
class SigmaOverride:
    """A user's own sds in place of the tables' (``--sigma-db``, ``--look-sd-db``), dB.

    ``sigma_db`` replaces the persistent part (the whole sigma of one look when no per-look part
    is given), ``look_sd_db`` the per-look part; None keeps the tables' own.
    """

    sigma_db: float | None = None
    look_sd_db: float | None = None

    def __post_init__(self) -> None:
        if self.sigma_db is not None and not (math.isfinite(self.sigma_db) and 0.0 < self.sigma_db <= 100.0):
            raise InputError(f"--sigma-db: must be > 0 dB and at most 100 dB, got {self.sigma_db:g}")
        if self.look_sd_db is not None and not (math.isfinite(self.look_sd_db) and 0.0 <= self.look_sd_db <= 100.0):
            raise InputError(f"--look-sd-db: must be >= 0 dB and at most 100 dB, got {self.look_sd_db:g}")

    def describe(self) -> str:
        parts = []
        if self.sigma_db is not None:
            parts.append(f"sigma {self.sigma_db:g} dB given")
        if self.look_sd_db is not None:
            parts.append(f"per-look sd {self.look_sd_db:g} dB given")
        return ", ".join(parts)


def detection_sigma_db(tables: Tables, ic: int, range_m, bearing_deg=None,
                       override: SigmaOverride | None = None) -> LevelSigma:
    """The level's sd of class ``ic`` in every band at given ranges (and bearings), dB.

    Parameters
    ----------
    tables : Tables
        The face (``acoustics.open_tables``).
    ic : int
        The class.
    range_m : array_like
        Ranges from the observer, m.
    bearing_deg : array_like, optional
        Bearings, deg, broadcast with ``range_m`` (tables with bearings).
    override : SigmaOverride, optional
        The user's sds in place of these.

    Returns
    -------
    LevelSigma
        Arrays of shape ``range_m.shape + (M,)``: persistent sqrt(noise_sd_db^2 + sd_K^2) with
        sd_K the tables' ``k_error_sd_db`` there (the class's where they have none), per-look 0
        (module docstring).
    """
    cls = tables.classes[ic]
    k_sd = np.asarray(tables.k_error_sd_at(ic, range_m, bearing_deg=bearing_deg), dtype=float)
    persistent = np.hypot(cls.noise_sd_db, k_sd)
    per_look = np.zeros_like(persistent)
    source = ("the class's source-level sd (noise_sd_db) and K's error sd ("
              + ("the grid's k_error_sd_db map" if tables.has_k_error_map else "the class's k_error_sd_db")
              + "), all persistent along a track")
    if override is not None and override.describe():
        if override.sigma_db is not None:
            persistent = np.full_like(persistent, override.sigma_db)
            source = override.describe()
        else:
            source = f"{override.describe()}; persistent: {source}"
        if override.look_sd_db is not None:
            per_look = np.full_like(per_look, override.look_sd_db)
    return LevelSigma(persistent_db=persistent, per_look_db=per_look, source=source)


__all__ = ["LevelSigma", "SigmaOverride", "detection_sigma_db"]
