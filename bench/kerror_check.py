"""The tables' own K error against BELLHOP run from the target, and how it grows where tables of
one position are read by an observer who moved away: what `acoustics.grid.kerror` takes its
tables' residual, its correlation length and the two growths from.

    python -m bench.kerror_check [--cache DIR] [--workers 2]

On the built-in shelf-break grid, for the surface ship class (TV, 8 m: the sea surface acts at
its end), observers at the grid's origin and 0.5, 1, 1.5, 3 and 6 km from it toward the four quarters (where
the water is deep enough for the observer: on the shelf to the north it is not), each
with targets on three bearings from the observer (60, 180 and 300 deg: none of the studies' own
geometries) every 250 m from 3 to 15 km; K from BELLHOP along each
target-to-observer geodesic with the area's own relief and water (`acoustics.builder.truthk`,
as ``tmakit simulate --truth bellhop``) less K from the origin's tables read from the observer,
as a moving observer reads them. Per line of targets: the mean (the offset that line keeps) and
the residual about it, and the part of the residual that is each band's own (the bands' interference
patterns are off each its own way: what the trackers may not read as range from the differences
between bands); fitted over the lines: the residual's sd at the origin and its growth g in
sd^2 = sd0^2 + (g d)^2 with the observer's distance d, the same for the bands' own part, the
offset's growth (the lines' means away from the origin less the origin's on the same bearing,
their RMS against d through zero),
and the residual's correlation length along range (the pooled autocorrelation falls to 1/e).
Both growths are also fitted as a jump and a slope, J^2 (1 - exp(-d / L)) + (g d)^2 (`fit_jump`),
from the observers 0.5, 1 and 1.5 km away beside those 3 and 6 km away: what a linear growth
through zero misses close to where the tables were computed.
Writes docs/results/kerror-check.json.
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from bench.harness import REPO, Session

CLASSES = ("TV",)
DISTANCES_M = (0.0, 500.0, 1000.0, 1500.0, 3000.0, 6000.0)
QUARTERS_DEG = (0.0, 90.0, 180.0, 270.0)
BEARINGS_DEG = (60.0, 180.0, 300.0)
RANGES_M = tuple(np.arange(3000.0, 15000.0 + 1.0, 250.0))


def lines(tables, provider, ic: int) -> list[dict]:
    """Each observer position and bearing's line of targets: BELLHOP's K less the tables' (R, M)."""
    from tracker.simulate import TruePaths

    cls = tables.classes[ic]
    r = np.asarray(RANGES_M)
    out = []
    for d in DISTANCES_M:
        for quarter in (QUARTERS_DEG if d > 0 else (0.0,)):
            if not observer_in_water(tables, d, quarter):
                continue
            ox, oy = d * math.sin(math.radians(quarter)), d * math.cos(math.radians(quarter))
            for bearing in BEARINGS_DEG:
                x = ox + r * math.sin(math.radians(bearing))
                y = oy + r * math.cos(math.radians(bearing))
                paths = TruePaths(ic=ic, obs_x_m=np.full(1, ox), obs_y_m=np.full(1, oy),
                                  obs_depth_m=tables.observer_depth_m, x_m=x[:, None], y_m=y[:, None],
                                  range_m=r[:, None], bearing_deg=np.full((r.size, 1), bearing),
                                  target_depth_m=cls.depth_m)
                truth = provider(paths)[:, 0, :]                                        # (R, M)
                table = tables.k_at(ic, r, bearing_deg=np.full(r.size, bearing))        # (R, M)
                out.append({"distance_m": d, "quarter_deg": quarter, "bearing_deg": bearing,
                            "diff_db": truth - table})
    return out


#: An observer position needs this much water below the observer's depth, m (an atlas leaves out
#: a position whose water is shallower than the observer, DESIGN.md "Area atlases").
OBSERVER_CLEARANCE_M = 20.0


def observer_in_water(tables, distance_m: float, quarter_deg: float) -> bool:
    """Whether the water at an observer position (``distance_m`` toward ``quarter_deg`` from the
    origin) is deeper than the observer by `OBSERVER_CLEARANCE_M`: the bottom along that radial."""
    bottom = float(np.interp(distance_m, tables.range_m, tables.bottom_at(np.array([quarter_deg]))[0]))
    return math.isfinite(bottom) and bottom >= tables.observer_depth_m + OBSERVER_CLEARANCE_M


#: A line whose offset exceeds this is another acoustic regime, not the tables a little off: an
#: observer moved up onto the shelf, its level from the basin tens of dB below what the slope's
#: tables give. The fit is made with every line (``all``: the error the trackers must allow for
#: wherever an observer takes tables of one position) and without these (``same_regime``).
REGIME_CHANGE_DB = 20.0


def fit(found: list[dict], step_m: float) -> dict:
    """The model's numbers from the lines (module docstring): fitted with every line and with the
    lines of the tables' own regime (`REGIME_CHANGE_DB`)."""
    usable = [line for line in found if np.isfinite(line["diff_db"]).all(axis=1).sum() >= 8]  # not over land
    same = [line for line in usable
            if np.abs(np.nanmean(line["diff_db"][np.isfinite(line["diff_db"]).all(axis=1)], axis=0)).max()
            <= REGIME_CHANGE_DB]
    return {"all": _fit(usable, step_m), "same_regime": _fit(same, step_m),
            "other_regime_lines": [{k: line[k] for k in ("distance_m", "quarter_deg", "bearing_deg")}
                                   for line in usable if line not in same]}


def _fit(found: list[dict], step_m: float) -> dict:
    rows = []
    for line in found:
        diff = line["diff_db"]
        ok = np.isfinite(diff).all(axis=1)
        mean = np.nanmean(diff[ok], axis=0)                                             # (M,)
        resid = diff - mean
        rows.append({**{k: line[k] for k in ("distance_m", "quarter_deg", "bearing_deg")},
                     "offset_db": [round(float(v), 2) for v in mean],
                     "residual_sd_db": round(float(np.sqrt(np.nanmean(resid[ok] ** 2))), 2),
                     "band_own_sd_db": round(band_own_sd_db(resid[ok]), 2),
                     "resid": np.where(ok[:, None], resid, np.nan)})
    origin = {r["bearing_deg"]: np.asarray(r["offset_db"]) for r in rows if r["distance_m"] == 0.0}
    base, away_km, excess = _origin_and_excess(rows, "residual_sd_db")
    shifts = [(r["distance_m"] / 1000.0, float(np.sqrt(np.mean((np.asarray(r["offset_db"])
                                                                - origin[r["bearing_deg"]]) ** 2))))
              for r in rows if r["distance_m"] > 0.0 and r["bearing_deg"] in origin]
    shifts_km = np.array([d for d, _ in shifts])
    shift2 = np.array([s * s for _, s in shifts])
    residual_growth = math.sqrt(growth_through_zero(away_km, excess))
    base_own, _, own_excess = _origin_and_excess(rows, "band_own_sd_db")
    own_growth = math.sqrt(growth_through_zero(away_km, own_excess))
    offset_growth = math.sqrt(growth_through_zero(shifts_km, shift2))
    jump = {"residual": fit_jump(away_km, excess), "offset": fit_jump(shifts_km, shift2)}
    series = np.concatenate([np.moveaxis(r["resid"], 1, 0) for r in rows])             # (lines x M, R)
    from acoustics.sensitivity.errormodel import _e_folding_m

    length = _e_folding_m(series, step_m)
    for r in rows:
        r.pop("resid")
    return {"residual_sd_db_at_origin": round(base, 3), "residual_growth_db_per_km": round(residual_growth, 3),
            "offset_growth_db_per_km": round(offset_growth, 3), "residual_length_m": round(length, 1),
            "band_own_sd_db_at_origin": round(base_own, 3), "band_own_growth_db_per_km": round(own_growth, 3),
            "residual_band_correlation_at_origin": round(1.0 - (base_own / base) ** 2, 3),
            "jump": jump, "lines": rows}


def _origin_and_excess(rows: list[dict], key: str) -> tuple[float, np.ndarray, np.ndarray]:
    """An sd of the lines (``key``, dB): its RMS over the lines at the origin, and each line away
    from it, its observer's distance, km, and its variance over the origin's, dB^2."""
    base = float(np.sqrt(np.mean([r[key] ** 2 for r in rows if r["distance_m"] == 0.0])))
    away = [r for r in rows if r["distance_m"] > 0.0]
    return (base, np.array([r["distance_m"] / 1000.0 for r in away]),
            np.array([r[key] ** 2 - base * base for r in away]))


def band_own_sd_db(resid: np.ndarray) -> float:
    """sd of each band's own part of a line's residual (R, M), dB: with resid_m = c + b_m, the
    deviation from the mean over the M bands is b_m less the bands' mean of b, whose variance is
    (1 - 1/M) that of b_m."""
    m = resid.shape[1]
    if m < 2:
        return 0.0
    dev = resid - resid.mean(axis=1, keepdims=True)
    return float(np.sqrt(np.mean(dev ** 2) * m / (m - 1)))


def growth_through_zero(d_km: np.ndarray, excess_db2: np.ndarray) -> float:
    """g^2 of excess(d) = (g d)^2 by least squares (0 where the excess falls with d), dB^2/km^2."""
    d2 = d_km ** 2
    return max(float(np.sum(d2 * excess_db2) / np.sum(d2 * d2)), 0.0)


#: The lengths over which the jump may rise (`fit_jump`), km.
JUMP_LENGTHS_KM = tuple(np.round(np.arange(0.1, 5.01, 0.05), 2))


def fit_jump(d_km: np.ndarray, excess_db2: np.ndarray) -> dict:
    """The growth of a variance with the observer's distance d as a jump and a slope,
    excess(d) = J^2 (1 - exp(-d / L)) + (g d)^2: tables read a little away from where they were
    computed meet their interference pattern shifted (two readings of one pattern a distance
    apart differ by a variance that rises to twice the pattern's over its correlation length),
    and the acoustic regime changes further on (the slope). J^2 and g^2 by non-negative least
    squares at each L of `JUMP_LENGTHS_KM`, the L of least squares kept; and the linear growth
    alone (J = 0) for comparison, its root mean square misfit beside."""
    from scipy.optimize import nnls

    best = None
    for length in JUMP_LENGTHS_KM:
        a = np.column_stack([1.0 - np.exp(-d_km / length), d_km ** 2])
        coef, misfit = nnls(a, excess_db2)
        if best is None or misfit < best[2]:
            best = (length, coef, misfit)
    length, (j2, g2), misfit = best
    g2_only = growth_through_zero(d_km, excess_db2)
    linear_misfit = float(np.sqrt(np.mean((excess_db2 - g2_only * d_km ** 2) ** 2)))
    return {"jump_db": round(math.sqrt(j2), 3), "jump_length_m": round(1000.0 * float(length), 1),
            "growth_db_per_km": round(math.sqrt(g2), 3),
            "rms_misfit_db2": round(float(misfit) / math.sqrt(d_km.size), 2),
            "linear_only_rms_misfit_db2": round(linear_misfit, 2),
            "mean_excess_db2_by_distance_km": {f"{d:g}": round(float(np.mean(excess_db2[d_km == d])), 2)
                                               for d in sorted(set(d_km.tolist()))}}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cache", default=str(REPO / "out" / "kerror-check" / "truth-runs"),
                        help="where BELLHOP's truth runs are kept (a rerun reuses them)")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args(argv)
    import acoustics
    import envdata
    from acoustics.builder.truthk import BellhopTruth

    session = Session("kerror-check")
    grid = REPO / "out" / "kerror-check" / "shelf-break-bellhop.nc"
    area = envdata.load_area("shelf-break")
    acoustics.build_grid_file(area, grid, workers=args.workers)
    tables = acoustics.open_tables(grid)
    provider = BellhopTruth(area, cache_dir=args.cache, workers=args.workers)
    by_class = {}
    for name in CLASSES:
        ic = tables.class_index(name)
        result = fit(lines(tables, provider, ic), RANGES_M[1] - RANGES_M[0])
        by_class[name] = result
        for part in ("all", "same_regime"):
            for key in ("residual_sd_db_at_origin", "residual_growth_db_per_km", "offset_growth_db_per_km",
                        "residual_length_m", "band_own_sd_db_at_origin", "band_own_growth_db_per_km",
                        "residual_band_correlation_at_origin"):
                unit = ("dB" if "sd_db" in key else "dB/km" if "growth" in key else "" if "correlation" in key
                        else "m")
                session.say(f"{name}_{part}_{key}", result[part][key], unit)
            for which, jump in result[part]["jump"].items():
                for key, unit in (("jump_db", "dB"), ("jump_length_m", "m"), ("growth_db_per_km", "dB/km")):
                    session.say(f"{name}_{part}_jump_fit_{which}_{key}", jump[key], unit)
    session.write(classes=by_class, distances_m=list(DISTANCES_M), quarters_deg=list(QUARTERS_DEG),
                  bearings_deg=list(BEARINGS_DEG), ranges_m=[RANGES_M[0], RANGES_M[-1], RANGES_M[1] - RANGES_M[0]],
                  truth_runs=provider.stats.runs, truth_runs_cached=provider.stats.cached)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
