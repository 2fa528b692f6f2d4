"""Write the sample data of the built-in ``shelf-break`` area (deterministic; ``python -m tools.make_sample_data``).

The files under ``envdata/areas/data/`` are synthetic, not GEBCO or World Ocean Atlas data, in
exactly those products' layouts (``tools.sample_layouts``), so that the readers see what users
download. The sea they describe is a plausible shelf break of the north-western Mediterranean
south of Provence, around the area's origin at 43.0 N 5.0 E:

Relief (GEBCO layout, 15 arc-seconds, 42.5-43.5 N, 4.4-5.6 E). In local coordinates about the
origin (x east, y north, km), the coast runs east-west near y = 22 km with a gentle undulation
and a headland reaching south to y ~ 12 km near x = 22 km; land rises inland at 30 m/km to
hills of 1000 m. The
shelf deepens from the coast to 130 m at the shelf break, y ~ 6 km (a power 0.7 of the distance
from the coast, so the inner shelf is shallow and the outer shelf gently sloping). Seaward of the
break the continental slope falls as a tanh, centred 12 km beyond the break, 8 km wide, to the
2500 m floor of the Algero-Provencal basin, steepest (~9 deg) on the mid-slope, as on this narrow
margin. A submarine canyon (a Gaussian trough 2 km wide, up to 300 m deep, 50 m into the outer
shelf) cuts the slope south-east of the origin, and a few metres of roughness break up the
floor. The origin lies on the upper slope (~540 m); radials towards the north and north-east
meet land within 30 km, those to the south reach the basin.

Temperature and salinity (WOA layout, 0.25 deg, the 57 monthly levels to 1500 m; cells whose
centre is on land hold no value, and levels below a cell's depth at its centre hold none,
as in WOA). A background of Western Mediterranean Deep Water (12.9 degC, 38.45) below Levantine
Intermediate Water (a warm, salty core near 400 m: +0.5 degC, +0.12) and fresher Modified
Atlantic Water at the top (-0.35 over 80 m). The seasonal cycle heats the surface from 13.2 degC
in February to 23.2 degC in August, mixed down over a layer 140 m thick in winter and 20 m in
summer, below which the warming decays over 55 m (winter) to 25 m (summer): a sharp summer
thermocline at 20-60 m, a nearly isothermal winter column. Near the coast the surface water is
cooler (-0.5 degC, wind-driven mixing) and fresher (-0.3, river water), fading over 15 km.

``envdata/areas/data/`` gets the August fields in WOA's own split (a temperature and a salinity
file, one time step each) and the relief; ``write_monthly`` writes all twelve months in one file.

A CTD cast at the origin in August, the same water continuous in depth, for the tests
(``--cast tests/data/casts``): ``shelf-ctd.cnv`` in Sea-Bird's layout, binned to 5 m down to 500 m,
and ``shelf-ctd.csv``, the same numbers in tmakit's CSV; ``cast_scans`` gives the cast as the CTD
records it, scan by scan, down and back up.
"""

from __future__ import annotations

import argparse
import datetime
from pathlib import Path

import numpy as np

from tools.sample_layouts import WOA_LEVELS_M, WOA_MONTHLY_LEVELS, gebco_axis_deg, write_cnv, write_gebco, write_woa

ORIGIN_LAT_DEG = 43.0
ORIGIN_LON_DEG = 5.0
KM_PER_DEG_LAT = 111.13
KM_PER_DEG_LON = 111.32 * np.cos(np.radians(ORIGIN_LAT_DEG))
SHELF_DEPTH_M = 130.0
BASIN_DEPTH_M = 2500.0
SLOPE_OFFSET_KM = 12.0  # centre of the slope's tanh beyond the shelf break
SLOPE_WIDTH_KM = 8.0
LAND_RISE_M_PER_KM = 30.0
LAND_TOP_M = 1000.0  # the hills of the coast
#: The box of the sample files, deg: wider than the radials' 30 km ahead and 5 km behind.
GEBCO_BOX = (42.5, 43.5, 4.4, 5.6)
WOA_LAT_DEG = np.arange(42.375, 43.7, 0.25)
WOA_LON_DEG = np.arange(4.125, 5.9, 0.25)
DATA = Path(__file__).resolve().parents[1] / "envdata" / "areas" / "data"
RELIEF_FILE = "shelf-break_gebco_15s.nc"
WOA_FILE = "shelf-break_woa_{kind}{month:02d}_04.nc"
CAST_STEM = "shelf-ctd"
CAST_START = datetime.datetime(2024, 8, 14, 6, 12, 9)
CAST_BOTTOM_M = 500.0  # the origin's floor is ~540 m down
CAST_BIN_M = 5.0


def local_km(lat_deg, lon_deg) -> tuple[np.ndarray, np.ndarray]:
    """Local east and north coordinates about the origin, km (equirectangular; synthetic relief only)."""
    return ((np.asarray(lon_deg) - ORIGIN_LON_DEG) * KM_PER_DEG_LON,
            (np.asarray(lat_deg) - ORIGIN_LAT_DEG) * KM_PER_DEG_LAT)


def coast_y_km(x_km):
    """North coordinate of the coast, km: undulating near 22 km, a headland near x = 22 km."""
    return 22.0 + 3.0 * np.sin(2 * np.pi * x_km / 37.0) - 9.0 * np.exp(-((x_km - 22.0) / 6.0) ** 2)


def shelf_break_y_km(x_km):
    """North coordinate of the shelf break, km."""
    return 6.0 + 1.5 * np.sin(2 * np.pi * x_km / 29.0 + 1.0)


def elevation_m(lat_deg, lon_deg) -> np.ndarray:
    """The synthetic relief, m above sea level (sea floor negative); see the module docstring."""
    x, y = local_km(lat_deg, lon_deg)
    x, y = np.broadcast_arrays(x, y)
    y_coast, y_break = coast_y_km(x), shelf_break_y_km(x)
    s = y - y_break  # north of the break, km

    def g(v):
        return 0.5 * (1.0 + np.tanh((-v - SLOPE_OFFSET_KM) / SLOPE_WIDTH_KM))

    g0 = g(0.0)
    slope = SHELF_DEPTH_M + (BASIN_DEPTH_M - SHELF_DEPTH_M) * (g(s) - g0) / (1.0 - g0)
    shelf = SHELF_DEPTH_M * np.clip((y_coast - y) / (y_coast - y_break), 0.0, None) ** 0.7
    depth = np.where(s < 0.0, slope, shelf)
    canyon_axis = 15.0 + 0.3 * y
    canyon = 300.0 * np.exp(-((s + 8.0) / 9.0) ** 2) * np.exp(-((x - canyon_axis) / 2.0) ** 2)
    roughness = 6.0 * np.sin(2 * np.pi * x / 3.1) * np.sin(2 * np.pi * y / 2.3)
    sea = -(depth + canyon + np.where(depth > 20.0, roughness, 0.0))
    land = np.minimum(LAND_RISE_M_PER_KM * (y - y_coast), LAND_TOP_M)
    return np.where(y >= y_coast, land, np.minimum(sea, -0.5))


def temperature_c(month: int, depth_m, lat_deg, lon_deg) -> np.ndarray:
    """In-situ temperature, degC, on (depth, lat, lon); see the module docstring."""
    z = np.asarray(depth_m, dtype=float)[:, None, None]
    x, y = local_km(*np.meshgrid(lat_deg, lon_deg, indexing="ij"))
    phase = 2 * np.pi * (month - 8) / 12.0  # 0 in August, pi in February
    background = 12.9 + 0.5 * np.exp(-((z - 400.0) / 300.0) ** 2)
    surface = 18.2 + 5.0 * np.cos(phase)  # 23.2 in August, 13.2 in February
    mixed = 80.0 - 60.0 * np.cos(phase)  # 20 m in August, 140 m in February
    decay = 40.0 - 15.0 * np.cos(phase)  # 25 m in August, 55 m in February
    shape = np.where(z <= mixed, 1.0, np.exp(-(z - mixed) / decay))
    warming = (surface - 12.98) * shape
    coastal = -0.5 * np.exp(-np.clip(coast_y_km(x) - y, 0.0, None) / 15.0) * np.exp(-z / 30.0)
    return background + warming + coastal


def salinity_psu(month: int, depth_m, lat_deg, lon_deg) -> np.ndarray:
    """Practical salinity on (depth, lat, lon); see the module docstring."""
    z = np.asarray(depth_m, dtype=float)[:, None, None]
    x, y = local_km(*np.meshgrid(lat_deg, lon_deg, indexing="ij"))
    phase = 2 * np.pi * (month - 8) / 12.0
    background = 38.45 + 0.12 * np.exp(-((z - 400.0) / 300.0) ** 2) - 0.35 * np.exp(-z / 80.0)
    evaporation = 0.08 * np.cos(phase) * np.exp(-z / 30.0)  # saltier surface at the end of summer
    coastal = -0.3 * np.exp(-np.clip(coast_y_km(x) - y, 0.0, None) / 15.0) * np.exp(-z / 25.0)
    return background + evaporation + coastal


def woa_mask(depth_m, lat_deg, lon_deg) -> np.ndarray:
    """(depth, lat, lon) True where WOA would have a value: the cell's centre is at sea and the
    level is not below the sea floor there."""
    lat, lon = np.meshgrid(lat_deg, lon_deg, indexing="ij")
    floor = -elevation_m(lat, lon)
    return np.asarray(depth_m, dtype=float)[:, None, None] <= floor[None, :, :]


def woa_fields(months, *, levels: int = WOA_MONTHLY_LEVELS):
    """Temperature and salinity (time, depth, lat, lon) in WOA's cells, NaN where WOA has none."""
    depth = WOA_LEVELS_M[:levels]
    mask = woa_mask(depth, WOA_LAT_DEG, WOA_LON_DEG)
    t = np.stack([np.where(mask, temperature_c(m, depth, WOA_LAT_DEG, WOA_LON_DEG), np.nan) for m in months])
    s = np.stack([np.where(mask, salinity_psu(m, depth, WOA_LAT_DEG, WOA_LON_DEG), np.nan) for m in months])
    return depth, t, s


def write_relief(path: Path) -> None:
    s, n, w, e = GEBCO_BOX
    lat, lon = gebco_axis_deg(s, n), gebco_axis_deg(w, e)
    write_gebco(path, lat, lon, elevation_m(lat[:, None], lon[None, :]),
                title="Synthetic shelf-break relief in the layout of the GEBCO 15 arc-second grid "
                      "(tmakit sample data, not GEBCO data)")


def write_month_split(folder: Path, month: int) -> tuple[Path, Path]:
    """WOA's split: one temperature and one salinity file for ``month``, one time step each."""
    depth, t, s = woa_fields([month])
    paths = []
    for kind, values, offset in (("t", t, 0.3), ("s", s, 0.05)):
        path = folder / WOA_FILE.format(kind=kind, month=month)
        write_woa(path, kind, [month], depth, WOA_LAT_DEG, WOA_LON_DEG, values, mean_offset=offset,
                  title=f"Synthetic shelf-break {'temperature' if kind == 't' else 'salinity'}, month "
                        f"{month}, in the layout of the World Ocean Atlas 2023 (tmakit sample data)")
        paths.append(path)
    return paths[0], paths[1]


def write_monthly(folder: Path, stem: str = "shelf-break_woa_monthly") -> tuple[Path, Path]:
    """All twelve months, one temperature and one salinity file with 12 time steps each."""
    months = list(range(1, 13))
    depth, t, s = woa_fields(months)
    paths = []
    for kind, values in (("t", t), ("s", s)):
        path = folder / f"{stem}_{kind}.nc"
        write_woa(path, kind, months, depth, WOA_LAT_DEG, WOA_LON_DEG, values,
                  title="Synthetic shelf-break climatology, 12 months, in the layout of the World Ocean "
                        "Atlas 2023 (tmakit sample data)")
        paths.append(path)
    return paths[0], paths[1]


def cast_ts(depth_m) -> tuple[np.ndarray, np.ndarray]:
    """In-situ temperature and practical salinity at the origin in August, at ``depth_m``."""
    at = (np.array([ORIGIN_LAT_DEG]), np.array([ORIGIN_LON_DEG]))
    return temperature_c(8, depth_m, *at)[:, 0, 0], salinity_psu(8, depth_m, *at)[:, 0, 0]


def write_cast(folder: Path) -> tuple[Path, Path]:
    """The binned down-cast at the origin: ``shelf-ctd.cnv`` (Sea-Bird) and ``shelf-ctd.csv``.

    The .cnv holds pressure, depth (the bin centres), T, S and Loop Edit's flag column, as SBE
    Data Processing's Bin Average writes them; the CSV the same depths, T and S to the same
    decimals, so that both read to the same numbers.
    """
    import gsw

    depth = np.arange(CAST_BIN_M, CAST_BOTTOM_M + CAST_BIN_M / 2, CAST_BIN_M)
    t, s = cast_ts(depth)
    pressure = gsw.p_from_z(-depth, ORIGIN_LAT_DEG)
    cnv = write_cnv(folder / f"{CAST_STEM}.cnv",
                    {"prDM": pressure, "depSM": depth, "t090C": t, "sal00": s, "flag": np.zeros(depth.size)},
                    latitude_deg=ORIGIN_LAT_DEG, longitude_deg=ORIGIN_LON_DEG, start=CAST_START,
                    interval=f"meters: {CAST_BIN_M:g}", station="shelf-break origin", bin_size_m=CAST_BIN_M)
    csv = folder / f"{CAST_STEM}.csv"
    rows = [f"{z:.3f},{tz:.4f},{sz:.4f}" for z, tz, sz in zip(depth, t, s)]
    csv.write_text("# The shelf-break origin in August binned to 5 m, the numbers of shelf-ctd.cnv "
                   "(tools/make_sample_data.py; synthetic)\n"
                   "depth_m,temperature_c,salinity_psu\n" + "\n".join(rows) + "\n")
    return cnv, csv


def cast_scans(*, rate_hz: float = 4.0, descent_mps: float = 1.0, bottom_m: float = CAST_BOTTOM_M,
               heave_m: float = 1.5, heave_period_s: float = 8.0, upcast_warmer_c: float = 0.3) -> dict:
    """The cast at the origin as the CTD records it, scan by scan: Sea-Bird columns -> values.

    A few scans on deck (pressure below 0, salinity ~0), the down-cast at ``descent_mps`` with the
    ship's heave (``heave_m`` at ``heave_period_s``: the CTD goes back up now and then, so depths
    do not increase scan by scan), then the up-cast, ``upcast_warmer_c`` warmer (a reader that
    mixes it in is caught). ``flag`` is 0: the file has not been through Loop Edit.
    """
    import gsw

    dt = 1.0 / rate_hz
    down_s = np.arange(0.0, (bottom_m - 2.0) / descent_mps, dt)
    down = 2.0 + descent_mps * down_s + heave_m * np.sin(2 * np.pi * down_s / heave_period_s)
    down = np.maximum(down, 0.3)
    up = bottom_m - descent_mps * np.arange(dt, (bottom_m - 2.0) / descent_mps, dt)
    deck = np.full(8, -0.2)
    depth = np.concatenate([deck, down, up])
    t, s = cast_ts(np.clip(depth, 0.0, None))
    t[: deck.size], s[: deck.size] = 26.0, 0.01  # air
    t[deck.size + down.size:] += upcast_warmer_c
    pressure = gsw.p_from_z(-depth, ORIGIN_LAT_DEG)
    return {"prDM": pressure, "depSM": depth, "t090C": t, "sal00": s,
            "timeS": dt * np.arange(depth.size), "flag": np.zeros(depth.size)}


def write_scans(path: Path, columns: dict, *, rate_hz: float = 4.0, **kwargs) -> Path:
    """Write ``cast_scans``'s columns (or a selection of them, or others) as an unbinned .cnv."""
    return write_cnv(path, columns, latitude_deg=ORIGIN_LAT_DEG, longitude_deg=ORIGIN_LON_DEG,
                     start=CAST_START, interval=f"seconds: {1.0 / rate_hz:g}", station="shelf-break origin",
                     **kwargs)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=DATA, help="folder to write to (default: %(default)s)")
    parser.add_argument("--cast", type=Path, metavar="FOLDER",
                        help="write the sample CTD cast (shelf-ctd.cnv, shelf-ctd.csv) to FOLDER instead")
    args = parser.parse_args(argv)
    if args.cast is not None:
        args.cast.mkdir(parents=True, exist_ok=True)
        for path in write_cast(args.cast):
            print(f"{path}: {path.stat().st_size / 1024:.0f} kB")
        return 0
    args.out.mkdir(parents=True, exist_ok=True)
    write_relief(args.out / RELIEF_FILE)
    for path in (args.out / RELIEF_FILE, *write_month_split(args.out, 8)):
        print(f"{path}: {path.stat().st_size / 1024:.0f} kB")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
