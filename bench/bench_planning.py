"""Detection planning on the built-in areas (docs/planning.md): P_D and its ranges per class and
band, how far each table would have to reach, the cumulative P_D along a scenario, shelf-break's
K beyond its 30 km measured against the extrapolation (and what the longer axis costs), and an
atlas's months side by side.

    python -m bench.bench_planning

Writes ``docs/results/planning.json`` and the figures in ``docs/results/planning/``:

- per built-in area (its BELLHOP grid in out/bench/, built or reused): for every class, band and
  any band the ranges where P_D = 0.9, 0.5, 0.1 (median, least and largest over the radials, and
  on how many the level passes the table's end), sigma, and ``grids build``'s range check
  (``acoustics.grid.pdmap.table_reach``); ``AREA-pd.png``, the figure ``tmakit grids plot FILE
  --what pd`` draws;
- shelf-break heard by the demo's sonar (``omni-buoy``: an omnidirectional hydrophone in sea
  state 6) and by the same in sea state 4: ranges in any band, the range check, and the demo's
  map ``shelf-break-pd-omni-buoy.png``;
- ``gm-nps`` on ocean-deep (``tmakit plan track``): the cumulative P_D at a few times, the first
  detection's times, with the tables' sigma (all persistent) and with a per-look part of 2 dB,
  and with the bands' offsets independent or shared; ``gm-nps-track.png``;
- shelf-break on four seaward and along-slope radials, built to 30 km and to 45 km (the relief
  the area ships reaches about 48 km), the builds interleaved, three times each after a warm-up, timed: K at 45 km
  against K's tail extrapolated from the 30 km table, and the median build time of each;
- the built-in shelf-break atlas area with the 12-month synthetic climatology (``python -m
  tests.fixtures.sample_data --monthly``), four months, radials every 90 deg and an array of
  `ATLAS_DI_DB` (the built-in 42 dB hears the submarine past the 20 km tables): its build time,
  every position's median ranges per month (``tmakit plan months``) for the submarine,
  ``atlas-months.png`` and August's map ``atlas-pd.png``.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from bench.harness import REPO, RESULTS_DIR, Session, bench_grid, median, portable_path

AREAS = ("ocean-deep", "shelf-break", "munk-1000")
FIGURES = RESULTS_DIR / "planning"
#: shelf-break's radials for the longer-axis check: down the slope, the canyon's side, along it.
CHECK_BEARINGS = (150.0, 180.0, 210.0, 270.0)
CHECK_RANGES_M = (30_000.0, 45_000.0)
#: Builds of each, interleaved after a warm-up of each (the machine is shared: read the ratio of
#: the medians).
CHECK_REPEATS = 3
#: The atlas: the built-in one with four months of the synthetic climatology.
ATLAS_MONTHS = (2, 5, 8, 11)
ATLAS_CLASS = "NPS"
#: Its array: smaller than the built-in 42 dB, so that the submarine's detection ends inside the
#: 20 km tables (K does not depend on it: only where detection ends).
ATLAS_DI_DB = 30.0
TRACK = ("ocean-deep", "gm-nps")
#: The demo's sonar also in Knudsen's sea state 4, dB re 1 uPa^2/Hz at 1 kHz (its own is 6).
SONAR_OTHER_SEA_DB = 66.5
TRACK_TIMES_S = (0.0, 600.0, 1200.0, 1800.0, 2400.0)


def _num(x, digits: int = 1):
    return None if x is None or not np.isfinite(x) else round(float(x), digits)


def level_ranges(pm) -> dict:
    """Per row (band or any), per level: median/least/largest range over the radials, m, and the
    radials where the level passes the table's end."""
    out = {}
    for i, row in enumerate(pm.rows):
        out[row] = {}
        for level, ranges in pm.ranges_m.items():
            past = pm.beyond[level][i]
            counted = np.where(past, np.inf, np.nan_to_num(ranges[i], nan=0.0))
            median = float(np.median(counted))
            given = ranges[i][np.isfinite(ranges[i])]
            out[row][f"{level:g}"] = {"median_m": _num(median), "min_m": _num(given.min()) if given.size else None,
                                      "max_m": _num(given.max()) if given.size else None,
                                      "beyond_table": int(past.sum()), "radials": int(past.size)}
    return out


def area_figures(session: Session) -> dict:
    import acoustics
    from acoustics.grid.pdmap import pd_map, table_reach
    from acoustics.plots.gridplots import PlotRequest, plot_grid
    from acoustics.plots.what import What
    from tools.pdtext import reach_data

    out = {}
    for area in AREAS:
        grid = bench_grid(area)
        tables = acoustics.open_tables(grid)
        bearings = tables.bearing_axis_deg if tables.bearing_axis_deg is not None else np.array([0.0])
        classes = {}
        for c in tables.class_names:
            pm = pd_map(tables, c, bearings)
            classes[c] = {"level": pm.terms.level_label, "sigma_db": round(float(np.max(pm.sigma.total_db)), 2),
                          "sigma": pm.sigma.source, "ranges": level_ranges(pm)}
        # what `tmakit grids plot GRID --what pd --band any --out PNG` writes; the PNG alone is kept
        with tempfile.TemporaryDirectory() as tmp:
            drawn = plot_grid(tables, Path(tmp) / "pd.png", PlotRequest(what=What.PD, band="any", grid_path=grid))
            png = FIGURES / f"{area}-pd.png"
            shutil.copyfile(drawn.files.get("map", drawn.files.get("pd")), png)
        reach = reach_data(table_reach(tables))
        out[area] = {"range_max_m": float(tables.range_m[-1]), "radials": int(bearings.size), "classes": classes,
                     "reach": reach, "figure": portable_path(png)}
        beyond = sum(not r["inside"] for r in reach)
        session.say(f"{area}_class_bands_beyond_table", beyond, f"of {len(reach)}")
    return out


def demo_sonar(session: Session) -> dict:
    """shelf-break heard by the demo's sonar (``tools.demo_cmd.MAP_SONAR``) in its own sea and in
    `SONAR_OTHER_SEA_DB`: the ranges per class in any band, the range check, and the demo's map."""
    import dataclasses

    import acoustics
    from acoustics.grid.pdmap import pd_map, table_reach
    from acoustics.plots.gridplots import PlotRequest, plot_grid
    from acoustics.plots.what import What
    from envdata.receiver import load_receiver
    from tools.demo_cmd import MAP_AREA, MAP_SONAR
    from tools.pdtext import reach_data

    grid = bench_grid(MAP_AREA)
    receiver = load_receiver(MAP_SONAR)
    seas = {"own": receiver,
            "sea_state_4": dataclasses.replace(receiver, noise=dataclasses.replace(
                receiver.noise, spectrum_level_1khz_db=SONAR_OTHER_SEA_DB))}
    out = {"area": MAP_AREA, "sonar": MAP_SONAR, "label": None, "seas": {}}
    area_tables = acoustics.open_tables(grid)   # opened once: each sea swaps only the sonar
    for name, rec in seas.items():
        tables = area_tables.with_receiver(rec)
        ranges = {c: level_ranges(pd_map(tables, c, tables.bearing_axis_deg))["any"] for c in tables.class_names}
        reach = reach_data(table_reach(tables))
        out["seas"][name] = {"noise_1khz_db": rec.noise.spectrum_level_1khz_db, "label": tables.sonar_label(),
                             "ranges_any": ranges, "reach": reach,
                             "class_bands_beyond_table": sum(not r["inside"] for r in reach)}
        session.say(f"{MAP_SONAR}_{name}_class_bands_beyond_table", out["seas"][name]["class_bands_beyond_table"],
                    f"of {len(reach)}")
        if name == "own":   # what `tmakit demo` draws (and `grids plot GRID --what pd --sonar omni-buoy`)
            out["label"] = tables.sonar_label()
            with tempfile.TemporaryDirectory() as tmp:
                drawn = plot_grid(tables, Path(tmp) / "pd.png", PlotRequest(what=What.PD, band="any", grid_path=grid))
                png = FIGURES / f"{MAP_AREA}-pd-{MAP_SONAR}.png"
                shutil.copyfile(drawn.files["map"], png)
            out["figure"] = portable_path(png)
    return out


def track_example(session: Session) -> dict:
    import acoustics
    from acoustics.grid.detectionsigma import SigmaOverride
    from acoustics.plots.figures import save_figure
    from tracker.pdtrack import scenario_path, track_pd, track_pd_figure
    from tracker.scenario import load_scenario

    area, scenario = TRACK
    tables = acoustics.open_tables(bench_grid(area))
    sc = load_scenario(scenario)
    out = {"area": area, "scenario": scenario, "class": sc.target_class, "cases": {}}
    for name, override in (("tables", None), ("look_sd_2db", SigmaOverride(look_sd_db=2.0))):
        result = track_pd(tables, scenario_path(sc), sc.target_class, override=override)
        t = result.path.t_s
        at = [int(np.argmin(np.abs(t - s))) for s in TRACK_TIMES_S]
        out["cases"][name] = {
            "sigma": result.sigma_source, "looks": int(t.size), "look_s": result.look_s,
            "t_s": [float(t[i]) for i in at], "range_m": [_num(result.range_m[i]) for i in at],
            "cum_pd": {row: [round(float(result.cumulative[i, j]), 4) for i in at]
                       for j, row in enumerate(result.rows)},
            "cum_pd_any_shared": [round(float(result.cumulative_shared[i]), 4) for i in at],
            "first_detection": result.first}
        if name == "tables":
            out["figure"] = portable_path(save_figure(track_pd_figure(result), FIGURES / f"{scenario}-track.png"))
        session.say(f"{scenario}_{name}_p_cum_start_any", float(result.cumulative[0, -1]))
    return out


def shelf_extension(session: Session, folder: Path) -> dict:
    """The shelf-break area on four radials to 30 and to 45 km: build times, and K at 45 km
    against the tail extrapolated from the 30 km table."""
    import acoustics
    import envdata
    from acoustics.builder.gridfile import build_grid_file
    from acoustics.grid.pdmap import pd_map, table_reach
    from acoustics.pd import tail_fit, tail_k_db

    text = envdata.area_path("shelf-break").read_text()
    text = text.replace('"data/', f'"{envdata.area_path("shelf-break").parent}/data/')
    text = text.replace("step_deg = 30.0", f"bearing_deg = {list(CHECK_BEARINGS)}")
    areas, builds = {}, {}
    for r_max in CHECK_RANGES_M:
        path = folder / f"shelf-{r_max / 1000:g}km.toml"
        path.write_text(text.replace("range_max_m = 30000.0", f"range_max_m = {r_max}"))
        areas[r_max] = (envdata.load_area(path), folder / f"{path.stem}.nc")
        builds[f"{r_max / 1000:g}km"] = (lambda a=areas[r_max]: build_grid_file(a[0], a[1], workers=2, force=True))
    for build in builds.values():   # a warm-up of each, not timed (the first build pays the imports and compiles)
        build()
    times = session.interleave(builds, repeats=CHECK_REPEATS)
    seconds = {r_max: median(times[f"{r_max / 1000:g}km"]) for r_max in CHECK_RANGES_M}
    for r_max in CHECK_RANGES_M:
        session.say(f"shelf_4_radials_build_{r_max / 1000:g}km", seconds[r_max], "s (median)",
                    runs=times[f"{r_max / 1000:g}km"])
    tables = {r_max: acoustics.open_tables(areas[r_max][1]) for r_max in CHECK_RANGES_M}
    short, long_ = (tables[r] for r in CHECK_RANGES_M)
    n = short.range_m.size
    beta = np.asarray(short.dataset["beta_db_per_km"].values, dtype=float)
    reach = {r_max: {(x.cls_name, x.band): x.needed_m for x in table_reach(t)} for r_max, t in tables.items()}
    per_class = {}
    for c in short.class_names:
        ic = short.class_index(c)
        a, m = tail_fit(short.range_m, short.k_grid_db[ic], beta[:, None])     # (M, N): the 30 km table's tail
        predicted = tail_k_db(a, m, beta[:, None], long_.range_m[n:])
        measured = long_.k_grid_db[ic][..., n:]                              # the ranges the 30 km table lacks
        pm = pd_map(long_, c, long_.bearing_axis_deg)
        per_class[c] = {
            "k_at_45km_db": np.round(measured[..., -1], 1).tolist(),
            "k_at_45km_from_the_30km_tail_db": np.round(predicted[..., -1], 1).tolist(),
            "k_30_to_45km_measured_minus_tail_median_db": round(float(np.nanmedian(measured - predicted)), 2),
            "se_at_45km_db": np.round(pm.excess_db[:, :, -1].T, 1).tolist(),
            "pd_at_45km": np.round(pm.edge_pd[:-1], 3).tolist(),
            "range_needed_m": {f"{r_max / 1000:g}km": [_num(reach[r_max][(c, b)], -2) for b in short.band_names]
                               for r_max in CHECK_RANGES_M}}
    ratio = seconds[CHECK_RANGES_M[1]] / seconds[CHECK_RANGES_M[0]]
    session.say("shelf_45km_over_30km_build_time", ratio, "x")
    return {"bearings_deg": list(CHECK_BEARINGS), "bands": list(short.band_names), "ranges_m": list(CHECK_RANGES_M),
            "build_seconds": {f"{r / 1000:g}km": round(s, 1) for r, s in seconds.items()},
            "build_runs_s": {k: [round(x, 1) for x in v] for k, v in times.items()},
            "build_time_ratio": round(ratio, 3), "classes": per_class}


def atlas_months(session: Session, folder: Path) -> dict:
    import envdata
    from acoustics.builder.atlas import build_atlas_file
    from acoustics.grid.atlas.seasons import position_maps, position_ranges
    from acoustics.grid.atlas.store import open_store
    from acoustics.grid.pdfile import atlas_pd_dataset, write_pd_file
    from acoustics.plots.atlaspd import atlas_pd_figure, seasons_figure
    from acoustics.plots.figures import save_figure

    subprocess.run([sys.executable, "-m", "tests.fixtures.sample_data", "--monthly", str(folder)], cwd=REPO, check=True)
    text = envdata.area_path("shelf-break-atlas").read_text()
    for old, new in (('bathymetry = "data/shelf-break_gebco_15s.nc"', 'bathymetry = "shelf-break_gebco_15s.nc"'),
                     ('temperature = "data/shelf-break_woa_t08_04.nc"', 'temperature = "woa_monthly_t.nc"'),
                     ('salinity = "data/shelf-break_woa_s08_04.nc"', 'salinity = "woa_monthly_s.nc"\nmonth = 8'),
                     ("depth_step_m = 50.0\n", f"depth_step_m = 50.0\nmonths = {list(ATLAS_MONTHS)}\n"),
                     ("step_deg = 30.0", "step_deg = 90.0"),
                     ("directivity_index_db = 42.0", f"directivity_index_db = {ATLAS_DI_DB}")):
        assert old in text, old
        text = text.replace(old, new)
    area = folder / "shelf-break-seasons.toml"
    area.write_text(text)
    start = time.perf_counter()
    info = build_atlas_file(envdata.load_area(area), folder / "seasons.zarr", workers=2)
    seconds = time.perf_counter() - start
    session.say("atlas_build_4_months", seconds, "s", runs=[seconds])
    store = open_store(folder / "seasons.zarr")
    rows, any_rows, by_month = [], [], {}
    for month in ATLAS_MONTHS:
        by_month[month] = position_maps(store, ATLAS_CLASS, month)
        for row in ("any", *store.band_names):
            ranges = position_ranges(store, month, by_month[month], row)
            rows += [{"row": row, **_as_dict(r)} for r in ranges]
            any_rows += ranges if row == "any" else []
    months_png = save_figure(seasons_figure(store, any_rows, cls_name=ATLAS_CLASS, row="any",
                                            months=list(ATLAS_MONTHS)), FIGURES / "atlas-months.png")
    august = [r for r in any_rows if r.month == 8]
    map_png = save_figure(atlas_pd_figure(store, month=8, cls_name=ATLAS_CLASS, row="any", maps=by_month[8],
                                          rows=august), FIGURES / "atlas-pd.png")
    write_pd_file(atlas_pd_dataset(store, 8, ATLAS_CLASS, "any"), folder / "atlas-pd.nc")
    return {"area": "shelf-break-atlas with the 12-month synthetic climatology", "months": list(ATLAS_MONTHS),
            "class": ATLAS_CLASS, "directivity_index_db": ATLAS_DI_DB, "positions": int(store.lat_deg.size),
            "radials": int(store.bearing_deg.size),
            "range_max_m": float(store.range_m[-1]), "tables": info["tables"], "runs": info["runs"],
            "build_seconds": round(seconds, 1), "rows": rows,
            "figures": [portable_path(months_png), portable_path(map_png)]}


def _as_dict(r) -> dict:
    import dataclasses

    return {k: (None if isinstance(v, float) and not np.isfinite(v) else v) for k, v in dataclasses.asdict(r).items()}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.parse_args(argv)
    FIGURES.mkdir(parents=True, exist_ok=True)
    session = Session("planning")
    with tempfile.TemporaryDirectory() as tmp:
        areas = area_figures(session)
        sonar = demo_sonar(session)
        track = track_example(session)
        extension = shelf_extension(session, Path(tmp))
        atlas = atlas_months(session, Path(tmp) / "atlas")
    session.write(areas=areas, demo_sonar=sonar, track=track, shelf_extension=extension, atlas=atlas)
    return 0


if __name__ == "__main__":
    sys.exit(main())
