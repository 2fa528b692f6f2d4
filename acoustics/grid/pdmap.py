"""P_D of a class along bearings from a grid's observer, its detection ranges per P_D level, and
where detection passes the table's last range (a P_D map).

K(r) is taken along the bearings as the detection map takes it (``acoustics.grid.detectionmap``,
between radials as the trackers do), sigma from ``acoustics.grid.detectionsigma``, P_D and the
ranges by ``acoustics.pd``. A level's range per bearing is the largest range of the table where
P_D >= the level; in a band that is where K(r) - sigma Phi^-1(p) passes the detection map's own
rule, so the 0.5 range of every band is the detection map's range to the metre. Where P_D still
reaches the level at the table's last range the range is "beyond the table" (NaN, flagged): the
table's edge is never given as a detection range. `table_reach` says, per class and band, how far
the range axis would have to go (``acoustics.pd.tail_reach_m``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from acoustics.absorption import thorp_db_per_km
from acoustics.detection import DetectionTerms, farthest_m
from acoustics.grid.detectionmap import class_k_db, class_terms
from acoustics.grid.detectionsigma import LevelSigma, SigmaOverride, detection_sigma_db
from acoustics.grid.face import Tables
from acoustics.pd import PD_LEVELS, any_band, normal_quantile, pd_of_excess, tail_reach_m
from envdata.errors import InputError

#: The name of the "any band" row (``--band any``).
ANY_BAND = "any"
#: The P_D level whose range the table should reach (``grids build`` says where it does not).
REACH_LEVEL = 0.1


@dataclass(frozen=True, slots=True, kw_only=True)
class PDMap:
    """P_D of one class per band (and any band) along bearings and ranges.

    Attributes
    ----------
    cls_name : str
    terms : DetectionTerms
        The class's mean level, the noise and the sonar.
    sigma : LevelSigma
        Its arrays (B, M, R), dB.
    bearing_deg : ndarray, shape (B,)
    range_m : ndarray, shape (R,)
    rows : tuple of str
        The bands, then ``"any"``: the order of the second axis of ``pd`` and of the ranges.
    excess_db : ndarray, shape (B, M, R)
        Signal excess SE = K(r) - K_needed, dB (NaN: no K, beyond land).
    pd : ndarray, shape (B, M + 1, R)
        P_D per band and of any band.
    ranges_m : dict
        level -> (M + 1, B): the largest range where P_D >= level, m; NaN where it never is and
        where it is beyond the table.
    beyond : dict
        level -> (M + 1, B) bool: P_D >= level at the table's last range.
    """

    cls_name: str
    terms: DetectionTerms
    sigma: LevelSigma
    bearing_deg: np.ndarray
    range_m: np.ndarray
    rows: tuple[str, ...]
    excess_db: np.ndarray
    pd: np.ndarray
    ranges_m: dict
    beyond: dict

    def row(self, band: str) -> int:
        """Index of a band or of ``"any"`` on the rows."""
        return self.rows.index(band)

    @property
    def edge_pd(self) -> np.ndarray:
        """P_D at the table's last range, (M + 1, B)."""
        return self.pd[:, :, -1].T


def _num(x: float, digits: int = 1):
    return None if not np.isfinite(x) else round(float(x), digits)


def pd_summary(pm: PDMap, *, with_bearings: bool = True) -> dict:
    """A P_D map as the ``--json`` summaries give it: the class's level, K needed and sigma; per
    band and any band the range of each P_D level per bearing (None where it is never reached or
    is beyond the table, ``beyond_table`` then true) and P_D at the table's last range.
    ``with_bearings`` False (tables without bearings): one value per level, not a list."""
    total = pm.sigma.total_db
    rows = {}
    for i, row in enumerate(pm.rows):
        one = {"range_m": {}, "beyond_table": {}}
        for level in pm.ranges_m:
            ranges = [_num(v) for v in pm.ranges_m[level][i]]
            past = [bool(v) for v in pm.beyond[level][i]]
            one["range_m"][f"{level:g}"] = ranges if with_bearings else ranges[0]
            one["beyond_table"][f"{level:g}"] = past if with_bearings else past[0]
        edge = [_num(v, 4) for v in pm.edge_pd[i]]
        one["pd_at_table_end"] = edge if with_bearings else edge[0]
        rows[row] = one
    return {"level_db": pm.terms.p0_db, "level": pm.terms.level_label,
            "k_needed_db": dict(zip(pm.rows, [round(float(v), 3) for v in pm.terms.k_needed_db()])),
            "sigma_db": {"min": round(float(np.min(total)), 3), "max": round(float(np.max(total)), 3)},
            "sigma": pm.sigma.source, "range_max_m": float(pm.range_m[-1]),
            "bearing_deg": [float(b) for b in pm.bearing_deg] if with_bearings else None, "rows": rows}


def check_band(tables: Tables, band: str | None) -> str:
    """A band of the tables or ``"any"`` (the default); InputError naming the choices otherwise."""
    if band is None or band == ANY_BAND:
        return ANY_BAND
    if band not in tables.band_names:
        raise InputError(f"{tables.source}: band {band!r} is not a band of the grid "
                         f"({', '.join(tables.band_names)}, or {ANY_BAND})")
    return band


def pd_map(tables: Tables, cls_name: str, bearing_deg, *, override: SigmaOverride | None = None,
           levels=PD_LEVELS) -> PDMap:
    """P_D of a class along bearings from the grid's observer (module docstring).

    Parameters
    ----------
    tables : Tables
        A grid or an atlas's table (``acoustics.open_tables``, ``AtlasStore.sel``).
    cls_name : str
        A class of the tables.
    bearing_deg : array_like, shape (B,)
        Bearings, deg (any for tables without bearings: every one is the same).
    override : SigmaOverride, optional
        The user's sigma in place of the tables' (``detection_sigma_db``).
    levels : sequence of float
        The P_D levels whose ranges to find, each in (0, 1).
    """
    bearings = np.atleast_1d(np.asarray(bearing_deg, dtype=float))
    terms = class_terms(tables, cls_name)
    ic = tables.class_index(cls_name)
    k = class_k_db(tables, cls_name, bearings)                                   # (B, M, R)
    rr = np.broadcast_to(tables.range_m, (bearings.size, tables.range_m.size))
    bb = None if tables.bearing_axis_deg is None else np.broadcast_to(bearings[:, None], rr.shape)
    sigma = detection_sigma_db(tables, ic, rr, bb, override)                    # (B, R, M)
    sigma = LevelSigma(persistent_db=np.moveaxis(sigma.persistent_db, -1, 1),
                       per_look_db=np.moveaxis(sigma.per_look_db, -1, 1), source=sigma.source)
    total = sigma.total_db
    excess = k - terms.k_needed_db()[None, :, None]
    pd_bands = pd_of_excess(excess, total)
    pd = np.concatenate([pd_bands, any_band(pd_bands, axis=1)[:, None, :]], axis=1)
    ranges, beyond = {}, {}
    for p in levels:
        z = normal_quantile(p)
        # the detection map's own rule on K shifted by sigma Phi^-1(p): at p = 1/2 exactly its step
        reached = np.concatenate([terms.detected(k - total * z), (pd[:, -1:, :] >= p)], axis=1)
        beyond[p] = reached[..., -1].T
        ranges[p] = np.where(beyond[p], np.nan, farthest_m(tables.range_m, reached).T)
    return PDMap(cls_name=cls_name, terms=terms, sigma=sigma, bearing_deg=bearings, range_m=tables.range_m,
                 rows=(*tables.band_names, ANY_BAND), excess_db=excess, pd=pd, ranges_m=ranges, beyond=beyond)


@dataclass(frozen=True, slots=True, kw_only=True)
class Reach:
    """Whether a class's detection in one band ends inside the table, and if not how far the
    range axis would have to go.

    Attributes
    ----------
    cls_name, band : str
    range_max_m : float
        The table's last range, m.
    edge_pd : float
        The largest P_D at the last range over the bearings.
    bearings_beyond : int
        Bearings where P_D >= `REACH_LEVEL` at the last range (of ``bearings``).
    bearings : int
    needed_m : float or None
        The range where P_D would fall to `REACH_LEVEL` on the farthest-reaching of those
        bearings, m, from K's tail (``acoustics.pd.tail_reach_m``); None when none passes.
    spreading_db_per_decade : float or None
        The spreading loss of that bearing's fitted tail, dB per decade of range.
    """

    cls_name: str
    band: str
    range_max_m: float
    edge_pd: float
    bearings_beyond: int
    bearings: int
    needed_m: float | None
    spreading_db_per_decade: float | None

    @property
    def inside(self) -> bool:
        return self.bearings_beyond == 0


def table_reach(tables: Tables, *, override: SigmaOverride | None = None, level: float = REACH_LEVEL
                ) -> list[Reach]:
    """Per class and band: does P_D fall below ``level`` inside the table (module docstring)?"""
    bearings = tables.bearing_axis_deg if tables.bearing_axis_deg is not None else np.array([0.0])
    if "beta_db_per_km" in tables.dataset:
        beta = np.asarray(tables.dataset["beta_db_per_km"].values, dtype=float)
    else:
        beta = thorp_db_per_km([b.center_hz for b in tables.bands])
    z = normal_quantile(level)
    out = []
    for cls_name in tables.class_names:
        pm = pd_map(tables, cls_name, bearings, override=override, levels=(level,))
        k = class_k_db(tables, cls_name, np.asarray(bearings, dtype=float))      # (B, M, R)
        target = pm.terms.k_needed_db()[None, :] + pm.sigma.total_db[:, :, -1] * z   # (B, M)
        reach, spread = tail_reach_m(tables.range_m, k, beta[None, :], target)
        for ib, band in enumerate(tables.band_names):
            past = pm.beyond[level][ib]
            needed = np.where(past, reach[:, ib], np.nan)
            best = int(np.nanargmax(needed)) if np.isfinite(needed).any() else None
            out.append(Reach(cls_name=cls_name, band=band, range_max_m=float(tables.range_m[-1]),
                             edge_pd=float(np.max(pm.edge_pd[ib])), bearings_beyond=int(past.sum()),
                             bearings=int(past.size),
                             needed_m=None if best is None else float(needed[best]),
                             spreading_db_per_decade=None if best is None else float(spread[best, ib])))
    return out


__all__ = ["ANY_BAND", "PDMap", "REACH_LEVEL", "Reach", "check_band", "pd_map", "pd_summary", "table_reach"]
