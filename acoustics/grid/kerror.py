"""K's error as tables know it, with its structure: what of it persists along a track, what
changes along it and over what range, and how it grows where tables computed at one position are
read from another (DESIGN.md "K's error and stated uncertainty").

The level a target gives is W = P0 + K(r) + dK + e (Grinenkov & Mashoshin eqs. 12, 31). dK, K's
error, is not new at every cycle: the tables' sea is wrong the same way from one cycle to the
next. Its parts, per class and band:

- the offset, persistent along a track (G&M's dK, drawn once per run), sd ``offset_sd_db``;
  between bands it is correlated by ``offset_band_correlation`` (the water or the bottom a
  little off moves every band's K alike);
- the residual, the part that changes along the track, sd ``residual_sd_db``, correlated over
  ``residual_length_m`` of the target's path relative to the observer: the sea's error field
  over range and bearing, and the tables' own fine error (their interference pattern a little
  off where the sea puts it), of which a part is each band's own (each band's pattern is off
  its own way: ``band_own_sd_db``), the rest split between bands as the offset is;
- for tables computed at one position (a bearing-dependent grid) read by an observer who moved
  d km from it, both grow: sd hypot(sd, growth x d); an atlas's blend reads each of its
  positions' tables away from that position, d the weighted mean of their distances.

An area file's one ``k_error_sd_db`` per class is the offset (what G&M's dK means); a
sensitivity study (``tmakit sensitivity --into``) measures every part from its members. The
tables' own residual and the growth away from their origin are measured against BELLHOP run from
the target on geometries none of the studies use (``python -m bench.kerror_check``,
docs/results/kerror-check.json: the shelf-break area, a surface ship at 8 m, observers at the
origin and 3 and 6 km toward the four quarters, targets every 250 m on three bearings), and hold
for every set of tables until a check of their own replaces them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from acoustics.grid.lookup import bearing_weights

#: The tables' own residual against BELLHOP run from the target, where nothing else differs
#: (observer at the tables' origin), dB: kerror-check.json ``classes.TV.all.residual_sd_db_at_origin``
#: (1.88 dB on the tables of the mirrored arrivals run, 2.13 dB before; the depth study's check of a
#: submarine at 3-60 m found 1.94 dB, docs/depth.md).
TABLE_RESIDUAL_SD_DB = 1.88
#: Its correlation length along the target's path relative to the observer, m: the same file's
#: ``same_regime.residual_length_m`` (780 m; with the lines of an observer moved onto the shelf,
#: whose tens of dB dominate the pooled correlation, 2520 m).
TABLE_RESIDUAL_LENGTH_M = 780.0
#: How the tables' residual grows with the observer's distance from where they were computed,
#: dB/km: the same file's ``all.residual_growth_db_per_km``: every line, an observer moved up onto
#: the shelf included (0.70 dB/km without those; the growth is far from uniform: tables of one
#: position hold where the water is like their origin's). Observers 0.5-1.5 km from the origin
#: (the same file's ``jump``) show the residual and the offset together rising no faster close to
#: it than these two growths give, on average.
TABLE_RESIDUAL_GROWTH_DB_PER_KM = 2.48
#: How the offset grows with that distance, dB/km (``all.offset_growth_db_per_km``: each line's
#: mean error less the origin's on the same bearing; 0.43 dB/km without the shelf's lines).
TABLE_OFFSET_GROWTH_DB_PER_KM = 3.10
#: The part of the tables' own residual that is each band's own, dB, within `TABLE_RESIDUAL_SD_DB`:
#: the same file's ``all.band_own_sd_db_at_origin`` (0.68 dB of 1.88: the residual's correlation
#: between bands 0.87). The bands' interference patterns are each off its own way, so the
#: differences between bands are not known exactly; a model whose residual is the same in every
#: band reads them as range, confidently and wrongly where the levels come from BELLHOP run from
#: the target (docs/uncertainty.md, "Each band's own error").
TABLE_BAND_OWN_SD_DB = 0.68
#: How that part grows with the observer's distance from where the tables were computed, dB/km,
#: within `TABLE_RESIDUAL_GROWTH_DB_PER_KM`: ``all.band_own_growth_db_per_km`` (0.26 dB/km without
#: the shelf's lines).
TABLE_BAND_OWN_GROWTH_DB_PER_KM = 0.67
#: A grid's measured model (``tmakit sensitivity --into``, `acoustics.sensitivity.errormodel`;
#: docs/formats.md): each variable's dimensions without and with bearings.
MODEL_VARS = {"k_offset_sd_db": (("class", "band"), ("class", "band", "bearing")),
              "k_residual_sd_db": (("class", "band"), ("class", "band", "bearing")),
              "k_residual_length_m": (("class",), ("class",)),
              "k_offset_band_correlation": (("class",), ("class",))}


@dataclass(frozen=True, slots=True, kw_only=True)
class KErrorModel:
    """K's error of one class (module docstring): sds per band, dB.

    Attributes
    ----------
    offset_sd_db : tuple of float
        sd of the persistent offset, per band.
    offset_band_correlation : float
        Correlation of the offset between bands, in [0, 1].
    residual_sd_db : tuple of float
        sd of the residual along the track, per band.
    residual_length_m : float
        Its correlation length along the target's path relative to the observer, m.
    offset_growth_db_per_km, residual_growth_db_per_km : float
        Growth of the sds with the observer's distance from where the tables were computed
        (0 for tables that hold everywhere: a flat area's; an atlas's grow with its blended
        positions' distance from the observer).
    band_own_sd_db, band_own_growth_db_per_km : float
        The part of the residual (of its sd, of its growth) that is each band's own, the same for
        every band, within ``residual_sd_db`` and ``residual_growth_db_per_km``: the tables' own
        (`TABLE_BAND_OWN_SD_DB`). The rest of the residual is split between bands as the offset is.
    source : str
        Where the numbers come from, for reports.
    """

    offset_sd_db: tuple[float, ...]
    offset_band_correlation: float = 1.0
    residual_sd_db: tuple[float, ...]
    residual_length_m: float = TABLE_RESIDUAL_LENGTH_M
    offset_growth_db_per_km: float = 0.0
    residual_growth_db_per_km: float = 0.0
    band_own_sd_db: float = 0.0
    band_own_growth_db_per_km: float = 0.0
    source: str = ""

    def __post_init__(self) -> None:
        if len(self.offset_sd_db) != len(self.residual_sd_db):
            raise ValueError("K error model: one offset sd and one residual sd per band")
        for name in ("offset_sd_db", "residual_sd_db"):
            for v in getattr(self, name):
                if not (math.isfinite(v) and v >= 0.0):
                    raise ValueError(f"K error model: {name} must be >= 0 dB, got {v}")
        if not 0.0 <= self.offset_band_correlation <= 1.0:
            raise ValueError(f"K error model: offset_band_correlation must be in [0, 1], got "
                             f"{self.offset_band_correlation}")
        if not (math.isfinite(self.residual_length_m) and self.residual_length_m > 0.0):
            raise ValueError(f"K error model: residual_length_m must be > 0, got {self.residual_length_m}")
        for name in ("offset_growth_db_per_km", "residual_growth_db_per_km"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0.0):
                raise ValueError(f"K error model: {name} must be >= 0 dB/km, got {v}")
        for name, whole in (("band_own_sd_db", min(self.residual_sd_db, default=0.0)),
                            ("band_own_growth_db_per_km", self.residual_growth_db_per_km)):
            v = getattr(self, name)
            if not (math.isfinite(v) and 0.0 <= v <= whole):
                raise ValueError(f"K error model: {name} must be in [0, {whole:g}] (a part of the residual's), "
                                 f"got {v}")

    @classmethod
    def of_class(cls, k_error_sd_db: float, n_bands: int, *, one_position: bool,
                 source: str = "the class's k_error_sd_db") -> KErrorModel:
        """An area file's one number as the offset (common to the bands), the tables' own
        residual beside it, growing away from the origin of tables computed at one position."""
        return cls(offset_sd_db=(float(k_error_sd_db),) * n_bands, offset_band_correlation=1.0,
                   residual_sd_db=(TABLE_RESIDUAL_SD_DB,) * n_bands, residual_length_m=TABLE_RESIDUAL_LENGTH_M,
                   offset_growth_db_per_km=TABLE_OFFSET_GROWTH_DB_PER_KM if one_position else 0.0,
                   residual_growth_db_per_km=TABLE_RESIDUAL_GROWTH_DB_PER_KM if one_position else 0.0,
                   **_tables_band_own(one_position), source=source)

    @classmethod
    def measured(cls, measured: MeasuredKError, ic: int, *, one_position: bool, bearing_deg=None) -> KErrorModel:
        """A study's model of class ``ic`` (at ``bearing_deg``, linear between radials; the median
        over them without one), its residual with the tables' own beside it (the members' K is
        computed as the tables' is, so their differences leave it out)."""
        off, res = measured.at_bearing(ic, bearing_deg)
        length = float(measured.residual_length_m[ic])
        corr = float(measured.band_correlation[ic])
        return cls(offset_sd_db=tuple(float(v) for v in off),
                   offset_band_correlation=corr if math.isfinite(corr) else 1.0,
                   residual_sd_db=tuple(math.hypot(float(v), TABLE_RESIDUAL_SD_DB) for v in res),
                   residual_length_m=length if math.isfinite(length) and length > 0 else TABLE_RESIDUAL_LENGTH_M,
                   offset_growth_db_per_km=TABLE_OFFSET_GROWTH_DB_PER_KM if one_position else 0.0,
                   residual_growth_db_per_km=TABLE_RESIDUAL_GROWTH_DB_PER_KM if one_position else 0.0,
                   **_tables_band_own(one_position), source=measured.source)

    def total_sd_db(self, displacement_m: float = 0.0) -> tuple[float, ...]:
        """sd of the whole K error of each band at one cycle (offset and residual), dB."""
        d = displacement_m / 1000.0
        return tuple(math.hypot(o, r, self.offset_growth_db_per_km * d, self.residual_growth_db_per_km * d)
                     for o, r in zip(self.offset_sd_db, self.residual_sd_db))


def _tables_band_own(one_position: bool) -> dict:
    """The tables' own residual's part that is each band's own, and its growth away from the
    origin of tables computed at one position."""
    return {"band_own_sd_db": TABLE_BAND_OWN_SD_DB,
            "band_own_growth_db_per_km": TABLE_BAND_OWN_GROWTH_DB_PER_KM if one_position else 0.0}


@dataclass(frozen=True, eq=False, kw_only=True)
class MeasuredKError:
    """A grid's measured model (`MODEL_VARS`): arrays by class, band (and bearing).

    Attributes
    ----------
    offset_sd_db, residual_sd_db : ndarray, shape (C, M) or (C, M, N)
        dB; NaN where the study had no K (the class's numbers then serve).
    residual_length_m, band_correlation : ndarray, shape (C,)
    bearing_deg : ndarray, shape (N,), or None
    fallback_offset_db : ndarray, shape (C,)
        The classes' one ``k_error_sd_db``, where a cell has none.
    source : str
    """

    offset_sd_db: np.ndarray
    residual_sd_db: np.ndarray
    residual_length_m: np.ndarray
    band_correlation: np.ndarray
    bearing_deg: np.ndarray | None
    fallback_offset_db: np.ndarray
    source: str = ""

    def at_bearing(self, ic: int, bearing_deg=None) -> tuple[np.ndarray, np.ndarray]:
        """Offset and residual sds of class ``ic`` per band, dB: at a bearing (linear between
        radials, across 0/360), or the median over the radials."""
        off, res = self.offset_sd_db[ic], self.residual_sd_db[ic]
        if self.bearing_deg is not None:
            if bearing_deg is None:
                with np.errstate(all="ignore"):
                    off, res = np.nanmedian(off, axis=-1), np.nanmedian(res, axis=-1)
            else:
                j, j1, w = (v.item() for v in bearing_weights(self.bearing_deg, float(bearing_deg)))
                off = (1.0 - w) * off[:, j] + w * off[:, j1]
                res = (1.0 - w) * res[:, j] + w * res[:, j1]
        off = np.where(np.isfinite(off), off, self.fallback_offset_db[ic])
        res = np.where(np.isfinite(res), res, 0.0)
        return off, res


__all__ = ["KErrorModel", "MODEL_VARS", "MeasuredKError", "TABLE_BAND_OWN_GROWTH_DB_PER_KM", "TABLE_BAND_OWN_SD_DB",
           "TABLE_OFFSET_GROWTH_DB_PER_KM", "TABLE_RESIDUAL_GROWTH_DB_PER_KM", "TABLE_RESIDUAL_LENGTH_M",
           "TABLE_RESIDUAL_SD_DB"]
