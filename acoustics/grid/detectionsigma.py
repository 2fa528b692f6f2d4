"""How far the level a target gives scatters about its class's mean, for P_D: the one place.

P_D = Phi(SE / sigma) (``acoustics.pd``) takes sigma from here, and so do the detection ranges,
the P_D maps, the cumulative P_D along a track and the range-axis check. The level is
W = P0 + K(r) + dK + e (DESIGN.md "K's error and stated uncertainty"); what scatters it about the
class's mean splits in two:

- ``persistent_db``: what holds along a track, drawn once per target: the class's source-level
  sd (``noise_sd_db``: one target is as loud all along its track), K's offset and K's residual
  (``Tables.k_error_model``, `acoustics.grid.kerror`: the class's one ``k_error_sd_db`` as the
  offset with the tables' own residual, or a sensitivity study's model, at the bearing asked).
  The residual changes along a track over ``k_residual_length_m`` of its relative path (600 m
  to a few km), tens of looks apart at an integration time of 10 s: counted here as lasting, so
  that a cumulative P_D does not take looks it has the same error in as independent chances.
- ``per_look_db``: what is drawn anew at every look (one per integration time), independently:
  0 dB of the tables' own (a user may give one, ``--look-sd-db``).

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
        Arrays of shape ``range_m.shape + (M,)``: persistent sqrt(noise_sd_db^2 + offset^2 +
        residual^2) of K's error model at each bearing (the observer where the tables were
        computed), per-look 0 (module docstring).
    """
    cls = tables.classes[ic]
    r = np.asarray(range_m, dtype=float)
    n = len(tables.bands)
    b = (np.full(r.shape, np.nan) if bearing_deg is None
         else np.broadcast_to(np.asarray(bearing_deg, dtype=float), r.shape))
    k_sd = np.empty(r.shape + (n,))
    model = None
    keys = np.unique(b[np.isfinite(b)]) if np.isfinite(b).any() else np.array([])
    for key in [None, *keys]:
        model = tables.k_error_model(ic, None if key is None else float(key))
        at = ~np.isfinite(b) if key is None else b == key
        k_sd[at] = np.hypot(np.asarray(model.offset_sd_db), np.asarray(model.residual_sd_db))
    persistent = np.hypot(cls.noise_sd_db, k_sd)
    per_look = np.zeros_like(persistent)
    source = (f"the class's source-level sd (noise_sd_db) and K's error ({model.source}: offset and residual), "
              f"both lasting along a track")
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
