"""Benchmark: BELLHOP3D's Nx2D mode (one run per frequency over every radial) against the per-radial
2-D BELLHOP runs of a bearing-dependent grid (issue: measure both, keep the better).

Run with ``make bench`` (or ``python -m bench.bench_nx2d``). Prints one line per figure,
``name: value unit``, and writes ``docs/results/nx2d.json`` (docs/nx2d.md is written from it).
Two areas, each with 12 radials, 3 bands and ranges to 30 km: the built-in ``shelf-break`` (real
bathymetry and climatology files) and the same area made flat (1000 m of Munk water), where the
two routes solve the same problem. Every timing is repeated ``NX2D_REPEATS`` times (default 3),
the routes interleaved, and the median reported: the machine is shared and noisy. 20 to 40
minutes on 2 cores, depending on their load.
"""

from __future__ import annotations

import os
import resource
import time

import numpy as np

import acoustics
import envdata
from acoustics.bellhop.exe import find_bellhop, find_bellhop3d
from acoustics.bellhop.shdfile import tl_from_pressure
from acoustics.builder.bandruns import BuildStats
from acoustics.builder.radial import bottom_on_grid_m, depth_axis_m, plan_radial_runs
from acoustics.builder.runs import execute_runs
from acoustics.nx2d.box3d import box_positions
from acoustics.nx2d.route import Nx2dStats, box_range_m, nx2d_fields, sample_area_box
from bench.harness import Session, portable_path
from envdata.radials import area_radials, geodesic_points

REPEATS = int(os.environ.get("NX2D_REPEATS", "3"))
AUDIBLE_DB = 120.0  # cells compared: the 2-D route's TL below this (deep shadows left out)


#: Prints the figures (the result file holds them in ``areas``, as measured).
session = Session("nx2d")


def say(name: str, value, unit: str = "") -> None:
    session.say(name, value, unit)


def flat_area() -> envdata.Area:
    """The shelf-break area (origin, radials, bands, classes, grid) over 1000 m of flat Munk water."""
    doc = envdata.load_area("shelf-break").to_dict()
    doc["area"] = {**doc["area"], "name": "shelf-break-flat",
                   "description": "shelf-break's radials over flat 1000 m Munk water"}
    doc["water"] = {"depth_m": 1000.0, "ssp": "munk"}
    return envdata.parse_area(doc, "shelf-break-flat")


def receivers_of(area, radials) -> np.ndarray:
    """The 2-D runs' receivers: the grid's depth axis plus the class depths (acoustics.builder.radial)."""
    depth = depth_axis_m(area, radials)
    return np.unique(np.concatenate([depth, [c.depth_m for c in area.classes]]))


def time_2d(area, workers: int) -> dict:
    stats = BuildStats()
    start = time.perf_counter()
    acoustics.build_grid(area, workers=workers, stats=stats)
    return {"wall_s": time.perf_counter() - start, "bellhop_s": stats.bellhop_seconds, "runs": stats.runs_total}


def time_nx2d(area, receivers, workers: int, groups: int, bathymetry_step_m=None):
    stats = Nx2dStats()
    start = time.perf_counter()
    env = sample_area_box(area, bathymetry_step_m=bathymetry_step_m)
    stats.sample_seconds = time.perf_counter() - start
    fields = nx2d_fields(area, receivers, env=env, workers=workers, bearing_groups=groups, stats=stats)
    out = {"wall_s": time.perf_counter() - start, "bellhop_s": stats.bellhop_seconds, "runs": stats.runs,
           "sample_s": stats.sample_seconds, "write_s": stats.write_seconds, "runs_wall_s": stats.wall_seconds}
    return out, fields, env


def agreement(area, radials, receivers, two_d, where, nx2d) -> dict:
    """|dTL| between the routes per bearing (all run frequencies together), over cells in the
    water (above the radial's bottom, before land) where the 2-D TL is below AUDIBLE_DB."""
    rng = area.grid.range_m()
    per_bearing = {j: [] for j in range(len(radials))}
    signed = {j: [] for j in range(len(radials))}
    per_freq: dict[float, list] = {}
    for key, (j, f) in where.items():
        a = tl_from_pressure(two_d[key], area.propagation.tl_max_db)
        b = tl_from_pressure(nx2d[f][j], area.propagation.tl_max_db)
        bottom = bottom_on_grid_m(area, radials[j])
        wet = receivers[:, None] <= np.nan_to_num(bottom, nan=-1.0)[None, :]
        cells = wet & (a < AUDIBLE_DB)
        per_bearing[j].append(np.abs(a - b)[cells])
        signed[j].append((b - a)[cells])
        per_freq.setdefault(f, []).append(np.abs(a - b)[cells])
    rows = []
    for j, parts in per_bearing.items():
        d = np.concatenate(parts)
        rows.append({"bearing_deg": radials[j].bearing_deg, "cells": int(d.size),
                     "median_db": float(np.median(d)), "p90_db": float(np.percentile(d, 90)),
                     "max_db": float(d.max()), "bias_db": float(np.median(np.concatenate(signed[j])))})
    everything = np.concatenate([np.concatenate(p) for p in per_bearing.values()])
    freqs = [{"freq_hz": f, "median_db": float(np.median(np.concatenate(p))),
              "p90_db": float(np.percentile(np.concatenate(p), 90))} for f, p in sorted(per_freq.items())]
    return {"per_bearing": rows, "per_frequency": freqs, "cells": int(everything.size),
            "median_db": float(np.median(everything)), "p90_db": float(np.percentile(everything, 90)),
            "tl_below_db": AUDIBLE_DB, "range_m": [float(rng[0]), float(rng[-1])]}


def environment_difference(area, radials, env) -> dict:
    """How the box's bottom and sound speed differ from the radials' along each radial."""
    rng = area.grid.range_m()
    rows = []
    for rad in radials:
        s, c = np.sin(np.radians(rad.bearing_deg)), np.cos(np.radians(rad.bearing_deg))
        bottom = bottom_on_grid_m(area, rad)
        ok = np.isfinite(bottom)
        box_bottom = env.bottom_at(rng[ok] * s, rng[ok] * c)
        dz = np.abs(box_bottom - bottom[ok])
        # sound speed: the 2-D 'Q' field (bilinear in range and depth) against the box's trilinear one
        r = rng[ok][::10]
        z = rad.ssp_depth_m
        q = np.stack([np.interp(r, rad.ssp_range_m, rad.speed_mps[k]) for k in range(z.size)])
        h = _trilinear(env, r * s, r * c, z)
        rows.append({"bearing_deg": rad.bearing_deg, "bottom_median_m": float(np.median(dz)),
                     "bottom_p90_m": float(np.percentile(dz, 90)), "bottom_max_m": float(dz.max()),
                     "speed_max_mps": float(np.max(np.abs(h - q)))})
    return {"per_bearing": rows}


def attribution(area, radials, receivers, env, nx2d, bearings=(30.0, 120.0, 240.0)) -> dict:
    """Where the shelf-break differences come from: the 2-D runs of a few oblique radials again,
    (a) as built, (b) with the bottom of BELLHOP3D's triangulated box along the radial (every
    facet edge it crosses), (c) with that bottom and the box's trilinear sound speed, each
    against the same Nx2D field (first run frequency)."""
    from envdata.radials import Radial

    chosen = [j for j, rad in enumerate(radials) if rad.bearing_deg in bearings]
    freq = min(nx2d)
    variants = {"as_built": (False, False), "facet_bottom": (True, False), "facet_bottom_box_speed": (True, True)}
    out = {"freq_hz": freq, "bearings_deg": [radials[j].bearing_deg for j in chosen]}
    for name, (facets, box_speed) in variants.items():
        remade = []
        for j in chosen:
            rad = radials[j]
            s, c = np.sin(np.radians(rad.bearing_deg)), np.cos(np.radians(rad.bearing_deg))
            kw = {f: getattr(rad, f) for f in ("bearing_deg", "range_m", "lat_deg", "lon_deg", "bottom_depth_m",
                                               "land_range_m", "ssp_range_m", "ssp_depth_m", "speed_mps")}
            if facets:
                r = _facet_crossings(env, rad, s, c)
                bottom = np.clip(_facet_bottom(env, r * s, r * c), 1.0, rad.max_depth_m)
                if rad.land_range_m is not None:
                    bottom[-1] = 1.0
                kw.update(range_m=r, lat_deg=np.zeros(r.size), lon_deg=np.zeros(r.size), bottom_depth_m=bottom)
            if box_speed:
                pr = np.linspace(rad.ssp_range_m[0], rad.ssp_range_m[-1], 61)
                kw.update(ssp_range_m=pr, speed_mps=_trilinear(env, pr * s, pr * c, rad.ssp_depth_m))
            remade.append(Radial(**kw))
        runs, where = plan_radial_runs(area, remade, receivers)
        keep = [run for run in runs if where[run.key][1] == freq]
        two_d = execute_runs(keep, workers=2)
        rows = []
        for run in keep:
            k = where[run.key][0]
            j = chosen[k]
            a = tl_from_pressure(two_d[run.key], area.propagation.tl_max_db)
            b = tl_from_pressure(nx2d[freq][j], area.propagation.tl_max_db)
            bottom = bottom_on_grid_m(area, radials[j])
            cells = (receivers[:, None] <= np.nan_to_num(bottom, nan=-1.0)[None, :]) & (a < AUDIBLE_DB)
            d = np.abs(a - b)[cells]
            rows.append({"bearing_deg": radials[j].bearing_deg, "median_db": float(np.median(d)),
                         "p90_db": float(np.percentile(d, 90))})
        out[name] = sorted(rows, key=lambda row: row["bearing_deg"])
    return out


def _facet_crossings(env, rad, s: float, c: float) -> np.ndarray:
    """Ranges along a radial where it crosses the box's node lines and cell diagonals (BELLHOP3D
    splits each square cell along its south-west to north-east diagonal), and its ends."""
    step = float(env.x_m[1] - env.x_m[0])
    m = np.arange(-(env.x_m.size + env.y_m.size), env.x_m.size + env.y_m.size + 1) * step
    parts = [np.array([rad.range_m[0], rad.range_m[-1]])]
    for k in (s, c, c - s):  # x = m, y = m, y - x = m (the grids start on multiples of the step)
        if abs(k) > 1e-9:
            parts.append(m / k)
    r = np.unique(np.concatenate(parts))
    r = r[(r >= rad.range_m[0]) & (r <= rad.range_m[-1])]
    return r[np.concatenate([[True], np.diff(r) > 1e-3])]


def _facet_bottom(env, x, y) -> np.ndarray:
    """The box's bottom as BELLHOP3D sees it: two planar triangles per cell."""
    xs, ys, z = env.x_m, env.y_m, env.bottom_depth_m
    i = np.clip(np.searchsorted(xs, x) - 1, 0, xs.size - 2)
    j = np.clip(np.searchsorted(ys, y) - 1, 0, ys.size - 2)
    u = (x - xs[i]) / (xs[i + 1] - xs[i])
    v = (y - ys[j]) / (ys[j + 1] - ys[j])
    z00, z10, z01, z11 = z[j, i], z[j, i + 1], z[j + 1, i], z[j + 1, i + 1]
    return np.where(v <= u, z00 + u * (z10 - z00) + v * (z11 - z10), z00 + v * (z01 - z00) + u * (z11 - z01))


def _trilinear(env, x, y, z) -> np.ndarray:
    """The box's sound speed at (x_i, y_i) and every depth of z, (Z, N): bilinear in x, y and
    linear in depth, as BELLHOP3D's hexahedral interpolation."""
    from scipy.interpolate import RegularGridInterpolator

    interp = RegularGridInterpolator((env.ssp_depth_m, env.ssp_y_m, env.ssp_x_m), env.speed_mps)
    zz, ii = np.meshgrid(z, np.arange(x.size), indexing="ij")
    return interp(np.stack([zz.ravel(), y[ii.ravel()], x[ii.ravel()]], axis=1)).reshape(zz.shape)


def geometry(area, range_m: float = 30000.0) -> dict:
    """Where a box's straight radial ends against the WGS84 geodesic, m: on tmakit's azimuthal
    equidistant box, and on a plain local flat-earth box (east = R_N cos(lat0) dlon, north = R_M dlat)."""
    from pyproj import Geod

    geod = Geod(ellps="WGS84")
    lat0, lon0 = area.origin.lat_deg, area.origin.lon_deg
    a, e2 = 6378137.0, 0.00669437999014
    phi = np.radians(lat0)
    r_n = a / np.sqrt(1 - e2 * np.sin(phi) ** 2)  # prime vertical radius
    r_m = a * (1 - e2) / (1 - e2 * np.sin(phi) ** 2) ** 1.5  # meridian radius
    aeqd, flat = [], []
    for bearing in area.bearings.bearing_deg:
        lat, lon = geodesic_points(lat0, lon0, bearing, [range_m])
        x, y = range_m * np.sin(np.radians(bearing)), range_m * np.cos(np.radians(bearing))
        blat, blon = box_positions(area, [x], [y])
        aeqd.append(geod.inv(lon[0], lat[0], blon[0], blat[0])[2])
        flat_lat = lat0 + np.degrees(y / r_m)
        flat_lon = lon0 + np.degrees(x / (r_n * np.cos(phi)))
        flat.append(geod.inv(lon[0], lat[0], flat_lon, flat_lat)[2])
    return {"range_m": range_m, "aeqd_max_offset_m": float(max(aeqd)), "flat_earth_max_offset_m": float(max(flat)),
            "aeqd_cross_radial_scale": float((range_m / 6371000.0) / np.sin(range_m / 6371000.0))}


def summary(values: list[float]) -> dict:
    return {"median": float(np.median(values)), "runs": [round(v, 3) for v in values]}


def bench_area(area, label: str, *, cell_variant: bool) -> dict:
    radials = area_radials(area)
    receivers = receivers_of(area, radials)
    configs = [("nx2d_workers1", 1, 1, None), ("nx2d_workers2", 2, 1, None), ("nx2d_workers2_groups2", 2, 2, None)]
    if cell_variant:  # the bottom on the bathymetry file's own cells instead of the radials' step
        cell_m = _bathymetry_cell_m(area)
        configs.append(("nx2d_cells_workers2_groups2", 2, 2, cell_m))
    times: dict[str, dict[str, list]] = {}
    fields = {}
    envs = {}

    def note(name: str, result: dict) -> None:
        for k, v in result.items():
            times.setdefault(name, {}).setdefault(k, []).append(v)

    for rep in range(REPEATS):
        for workers in (1, 2):
            note(f"2d_workers{workers}", time_2d(area, workers))
        rss_2d = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0
        for name, workers, groups, step in configs:
            result, fields[name], envs[name] = time_nx2d(area, receivers, workers, groups, step)
            note(name, result)
        print(f"# {label}: repeat {rep + 1}/{REPEATS} done", flush=True)
    rss_all = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0

    runs, where = plan_radial_runs(area, radials, receivers)
    two_d = execute_runs(runs, workers=2)
    env = envs["nx2d_workers1"]
    out = {
        "bearings": len(radials), "bands": len(area.bands), "range_max_m": area.grid.range_max_m,
        "receiver_depths": int(receivers.size), "ranges": int(area.grid.range_m().size),
        "beams": area.propagation.n_beams, "step_m": area.propagation.step_m,
        "runs_2d": len(runs), "frequencies": len(where) // len(radials),
        "box": {"ray_box_half_width_m": box_range_m(area), "grid_half_width_m": env.bathymetry_half_width_m(),
                "bathymetry_nodes": [int(env.x_m.size), int(env.y_m.size)],
                "bathymetry_step_m": float(env.x_m[1] - env.x_m[0]),
                "ssp_columns": [int(env.ssp_x_m.size), int(env.ssp_y_m.size)],
                "ssp_depths": int(env.ssp_depth_m.size), "deepest_m": env.max_depth_m},
        "times_s": {name: {k: summary(v) for k, v in parts.items()} for name, parts in times.items()},
        "peak_child_rss_mib": {"bellhop": rss_2d, "bellhop_and_bellhop3d": rss_all},
        "agreement": agreement(area, radials, receivers, two_d, where, fields["nx2d_workers1"]),
    }
    if cell_variant:
        cells = envs["nx2d_cells_workers2_groups2"]
        out["box_cells"] = {"bathymetry_nodes": [int(cells.x_m.size), int(cells.y_m.size)],
                            "bathymetry_step_m": float(cells.x_m[1] - cells.x_m[0])}
        out["agreement_cells"] = agreement(area, radials, receivers, two_d, where,
                                           fields["nx2d_cells_workers2_groups2"])
        out["environment_difference"] = environment_difference(area, radials, env)
        out["attribution"] = attribution(area, radials, receivers, env, fields["nx2d_workers1"])
    return out


def _bathymetry_cell_m(area) -> float:
    from envdata.bathymetry import open_bathymetry

    with open_bathymetry(area.water.bathymetry) as bathy:
        return float(bathy.axes.cell_m(area.origin.lat_deg))


def report(label: str, res: dict) -> None:
    t = res["times_s"]
    for name in t:
        say(f"{label}_{name}_wall", t[name]["wall_s"]["median"], f"s (median of {REPEATS})")
        say(f"{label}_{name}_bellhop_process_sum", t[name]["bellhop_s"]["median"], "s")
    for name in [n for n in t if n.startswith("nx2d")][:1]:
        say(f"{label}_nx2d_sample_box", t[name]["sample_s"]["median"], "s")
        say(f"{label}_nx2d_write_files", t[name]["write_s"]["median"], "s")
    say(f"{label}_speed_2d_over_nx2d_bellhop_time",
        t["nx2d_workers1"]["bellhop_s"]["median"] / t["2d_workers1"]["bellhop_s"]["median"], "x")
    say(f"{label}_speed_2d_over_nx2d_wall_2_workers",
        t["nx2d_workers2_groups2"]["wall_s"]["median"] / t["2d_workers2"]["wall_s"]["median"], "x")
    ag = res["agreement"]
    say(f"{label}_dtl_median", ag["median_db"], f"dB ({ag['cells']} cells, TL < {AUDIBLE_DB:g} dB)")
    say(f"{label}_dtl_p90", ag["p90_db"], "dB")
    for row in ag["per_bearing"]:
        say(f"{label}_dtl_bearing_{row['bearing_deg']:g}_median", row["median_db"], "dB")
        say(f"{label}_dtl_bearing_{row['bearing_deg']:g}_p90", row["p90_db"], "dB")
    if "agreement_cells" in res:
        ag = res["agreement_cells"]
        step = res["box_cells"]["bathymetry_step_m"]
        say(f"{label}_cells_dtl_median", ag["median_db"], f"dB (bottom on {step:.0f} m nodes)")
        say(f"{label}_cells_dtl_p90", ag["p90_db"], "dB")
    if "attribution" in res:
        for name in ("as_built", "facet_bottom", "facet_bottom_box_speed"):
            for row in res["attribution"][name]:
                say(f"{label}_2d_{name}_vs_nx2d_bearing_{row['bearing_deg']:g}_median", row["median_db"], "dB")
                say(f"{label}_2d_{name}_vs_nx2d_bearing_{row['bearing_deg']:g}_p90", row["p90_db"], "dB")


def _relative(described: dict) -> dict:
    """An executable's description with its path as a result file may name it (`portable_path`)."""
    return {**described, "path": portable_path(described["path"])} if described.get("path") else described


def main() -> None:
    results = {"repeats": REPEATS, "bellhop": _relative(find_bellhop().describe()),
               "bellhop3d": _relative(find_bellhop3d().describe())}
    shelf = envdata.load_area("shelf-break")
    results["geometry"] = geometry(shelf)
    say("geometry_aeqd_offset_at_30km", results["geometry"]["aeqd_max_offset_m"], "m")
    say("geometry_flat_earth_offset_at_30km", results["geometry"]["flat_earth_max_offset_m"], "m")
    results["areas"] = {}
    for label, area, cells in (("flat", flat_area(), False), ("shelf", shelf, True)):
        res = bench_area(area, label, cell_variant=cells)
        results["areas"][area.name] = res
        report(label, res)
    session.figures.clear()  # the result file keeps the measured structure, not the printed lines
    session.write(**results)


if __name__ == "__main__":
    main()
