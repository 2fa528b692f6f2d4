"""The depth study's check of the tables against BELLHOP run from the target, where nothing
else differs (no motion, no tracker): what `tracker.depth.errors.LevelErrors` takes its sds and
their growth with the observer's distance from (docs/depth.md, `tools.studies.depth`)."""

from __future__ import annotations

import math

import numpy as np

from tracker.depth.likelihood import TrackDepthLikelihood
from tracker.simulate import TruePaths

#: The tables against BELLHOP from the target (``tracker.depth.errors.LevelErrors`` takes its fine
#: sds and their growth from it): observers at the grid's origin and away from it (x east, y north,
#: m; the origin's tables read from there, as a moving observer reads them), each with targets on
#: one bearing (deg; 150 is a radial, 165 halfway between two) at these ranges (m) and depths (m).
CHECK_GEOMETRIES = ((0.0, 0.0, 150.0), (0.0, 0.0, 165.0), (-2500.0, 0.0, 150.0), (0.0, -2500.0, 165.0),
                    (-5000.0, 0.0, 150.0), (0.0, -5000.0, 165.0))
CHECK_RANGES_M = tuple(float(r) for r in range(3000, 20001, 1000))
CHECK_DEPTHS_M = (3.0, 6.0, 10.0, 20.0, 60.0)


def table_check(tables, provider, ic: int, span_m) -> dict:
    """K from BELLHOP with the source at the target (the truth's runs) less the tables' K (read as
    the depth likelihood reads it, from the observer) for each of `CHECK_GEOMETRIES`: per depth,
    the mean, the bands' offsets from it (and their sd), and the sd along range of the part common
    to the bands and of each band's own, dB, and the common part's correlation from one range to
    the next (`CHECK_RANGES_M`'s step); per geometry their medians over the depths; and the
    sds and growth they give (``fit``; ``fine``: the common part, ``fine_band``: each band's own,
    ``band``: the bands' offsets): the sd where the tables were computed (the median over the
    origin's geometries) and the growth g of sd^2 = sd_0^2 + (g d)^2 fitted (least squares) to
    the medians away from it, dB/km; ``offset``: how the mean moves with the observer, each
    depth's mean less the origin's on the same bearing (RMS over the depths), its growth fitted
    through zero at the origin (the offset's own sd there is the class's). ``provider`` gives
    BELLHOP's K along `tracker.simulate.TruePaths` (`acoustics.builder.truthk.BellhopTruth`);
    ``span_m`` the depths the likelihood's tables are read over."""
    r = np.asarray(CHECK_RANGES_M)
    like = TrackDepthLikelihood(tables, ic, tables.band_names, span_m)
    geometries = []
    for ox, oy, bearing in CHECK_GEOMETRIES:
        x, y = ox + r * math.sin(math.radians(bearing)), oy + r * math.cos(math.radians(bearing))
        out = {}
        for z in CHECK_DEPTHS_M:
            paths = TruePaths(ic=ic, obs_x_m=np.full(1, ox), obs_y_m=np.full(1, oy),
                              obs_depth_m=tables.area.observer.depth_m, x_m=x[:, None], y_m=y[:, None],
                              range_m=r[:, None], bearing_deg=np.full((r.size, 1), bearing), target_depth_m=z)
            k_truth = provider(paths)[:, 0, :]                                          # (R, M)
            k_table = np.stack([m.at(z, r, bearing) for m in like._mean], axis=-1)
            d = k_truth - k_table
            d0 = d - np.nanmean(d)
            band = np.nanmean(d0, axis=0)
            common = np.nanmean(d0 - band, axis=1)
            own = d0 - band - common[:, None]
            out[f"{z:g}"] = {"mean_db": round(float(np.nanmean(d)), 2),
                             "band_offsets_db": [round(float(v), 2) for v in band],
                             "band_offset_sd_db": round(float(np.std(band)), 2),
                             "common_sd_db": round(float(np.nanstd(common)), 2),
                             "common_lag1_correlation": round(_lag1_correlation(common), 2),
                             "band_own_sd_db": round(float(np.nanstd(own)), 2)}
        g = {"observer_x_m": ox, "observer_y_m": oy, "bearing_deg": bearing,
             "distance_km": round(math.hypot(ox, oy) / 1e3, 2), "by_depth_m": out}
        for key in ("common_sd_db", "band_own_sd_db", "band_offset_sd_db", "common_lag1_correlation"):
            g[f"median_{key}"] = round(float(np.median([v[key] for v in out.values()])), 2)
        geometries.append(g)
    fit = {}
    for key, name in (("common_sd_db", "fine"), ("band_own_sd_db", "fine_band"), ("band_offset_sd_db", "band")):
        base = float(np.median([g[f"median_{key}"] for g in geometries if g["distance_km"] == 0.0]))
        away = [(g["distance_km"], g[f"median_{key}"]) for g in geometries if g["distance_km"] > 0.0]
        fit[f"{name}_sd_db"] = round(base, 2)
        fit[f"{name}_growth_db_per_km"] = round(_growth(base, away), 2)
    # the offset common to the bands moves with the observer too, by depth: each depth's mean
    # less the origin's on the same bearing, their RMS over the depths
    origin = {g["bearing_deg"]: g["by_depth_m"] for g in geometries if g["distance_km"] == 0.0}
    shifts = [(g["distance_km"], math.sqrt(np.mean([(v["mean_db"] - origin[g["bearing_deg"]][z]["mean_db"]) ** 2
                                                    for z, v in g["by_depth_m"].items()])))
              for g in geometries if g["distance_km"] > 0.0 and g["bearing_deg"] in origin]
    fit["offset_growth_db_per_km"] = round(_growth(0.0, shifts), 2)
    return {"ranges_km": [CHECK_RANGES_M[0] / 1e3, CHECK_RANGES_M[-1] / 1e3], "geometries": geometries, "fit": fit}


def _lag1_correlation(x) -> float:
    """Correlation of a series with itself one step on (NaN-free pairs)."""
    a, b = np.asarray(x[:-1], dtype=float), np.asarray(x[1:], dtype=float)
    ok = np.isfinite(a) & np.isfinite(b)
    return float(np.corrcoef(a[ok], b[ok])[0, 1]) if ok.sum() > 2 else math.nan


def _growth(base: float, away) -> float:
    """The growth g of sd^2 = base^2 + (g d)^2 fitted by least squares to (d km, sd dB) pairs,
    dB/km (0 where they are no larger than the base)."""
    d2 = np.array([d * d for d, _ in away])
    excess = np.array([sd * sd - base * base for _, sd in away])
    return math.sqrt(max(float(np.sum(d2 * excess) / np.sum(d2 * d2)), 0.0))
