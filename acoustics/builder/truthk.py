"""K along the true paths by BELLHOP: the levels a simulator hears when they do not come from tables.

README "Atlases" (``tmakit simulate --truth bellhop``): each cycle's K is computed by BELLHOP
along the WGS84 geodesic from the target's true position to the observer's, with the area's own
bathymetry and water sampled along it (``envdata.radials.area_radials`` of a one-radial area
whose ``[origin]`` is the target and whose bearing points at the observer), the source at the
target's depth (with its source pattern where the surface acts there: the surface at the target's
end, as the flat grids) and one receiver at the observer's depth and range. No reciprocity, no
grid spacing, no interpolation between radials or positions: what the tables approximate.

The band TL is formed from the run frequencies exactly as a grid's (``band_tl_from_runs``,
the class's spectrum over the band), K = S - TL (eqs. 12-13). Positions are rounded to
``position_step_m`` in the local plane before the runs are written, so a run is named by its
rounded geometry (the run key hashes its input files): the same geometry runs once, and a
cache folder keeps the runs for the next simulation (``acoustics.builder.executor``; threads
or a Dask cluster). A geodesic that meets land before the observer gives no level (NaN).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from acoustics.bellhop.exe import find_bellhop
from acoustics.bellhop.radialfiles import radial_files
from acoustics.bellhop.shdfile import tl_from_pressure
from acoustics.builder.bandruns import band_tl_from_runs, freq_key, run_frequencies_hz, run_pattern, run_timeout_s
from acoustics.builder.plan import run_spec
from acoustics.builder.radial import BOX_MARGIN, DEFAULT_STEP_M, origin_speed_of
from acoustics.builder.runs import Run, RunStats, iter_runs
from acoustics.kcurve import spectral_term_db
from envdata.area import Area, GridSpec, Observer
from envdata.errors import AreaError
from envdata.geometry import Bearings, Origin, local_plane_to_lat_lon
from envdata.radials import area_radials, geodesic_points
from envdata.watersources import WaterSources, load_bathymetry_box, load_climatology_box

#: Positions are rounded to this in the local plane before a path is computed, m.
POSITION_STEP_M = 25.0
#: The radial starts this far behind the target (rays leaving it backwards), m.
BEHIND_M = 2000.0


@dataclass
class TruthStats:
    """What the truth runs did: geometries, BELLHOP runs (and of them from the cache), seconds."""

    paths: int = 0
    runs: int = 0
    cached: int = 0
    bellhop_seconds: float = 0.0
    wall_seconds: float = 0.0


@dataclass(frozen=True, slots=True)
class _Path:
    """One rounded geometry: target and observer positions (m, plane) and depths (m)."""

    x_m: float
    y_m: float
    obs_x_m: float
    obs_y_m: float
    depth_m: float
    obs_depth_m: float


@dataclass(eq=False)
class BellhopTruth:
    """A simulator's K provider (``tracker.simulate.simulate_batch(k_provider=...)``) by BELLHOP.

    Parameters
    ----------
    area : Area
        The area with ``[origin]`` (the local plane's reference) and its data files; the month's
        water of an atlas.
    cache_dir : path, optional
        Where finished runs are kept (a rerun reuses them).
    workers : int
        BELLHOP runs at once on local threads.
    scheduler : str, optional
        A trusted Dask scheduler to run them on instead.
    position_step_m : float
        Rounding of the positions, m.
    """

    area: Area
    cache_dir: str | Path | None = None
    workers: int = 2
    scheduler: str | None = None
    position_step_m: float = POSITION_STEP_M
    progress: bool = False
    stats: TruthStats = field(default_factory=TruthStats)

    def __post_init__(self) -> None:
        if self.area.origin is None or self.area.bearings is None:
            raise AreaError(f"area {self.area.name!r}: BELLHOP along the true paths needs an area with [origin] "
                            f"and its bathymetry and water (a bearing-dependent grid or an atlas)")

    @classmethod
    def beside(cls, area: Area, grid_path: str | Path, **kwargs) -> BellhopTruth:
        """The provider for the area stored in a grid or an atlas, its data files looked for as
        named, beside the grid file and in the built-in area of that name's folder."""
        from envdata.areafile import area_path, builtin_area_names
        from envdata.datafiles import with_files_found

        folders = [Path(grid_path).parent]
        if area.name in builtin_area_names():
            folders.append(area_path(area.name).parent)
        return cls(with_files_found(area, folders), **kwargs)

    def __call__(self, paths) -> np.ndarray:
        """K of class ``paths.ic`` in every band along each run's and cycle's true path, (E, T, M), dB.

        ``paths`` has ``ic``, ``obs_x_m``, ``obs_y_m`` (T,), ``obs_depth_m``, ``x_m``, ``y_m``
        (E, T) and ``target_depth_m`` (``tracker.simulate.TruePaths``).
        """
        step = self.position_step_m
        x = np.asarray(paths.x_m, dtype=float)
        y = np.asarray(paths.y_m, dtype=float)
        ox = np.broadcast_to(np.asarray(paths.obs_x_m, dtype=float), x.shape)
        oy = np.broadcast_to(np.asarray(paths.obs_y_m, dtype=float), x.shape)

        def rounded(v):
            return float(np.round(v / step) * step)

        keys = np.empty(x.shape, dtype=object)
        for idx in np.ndindex(x.shape):
            keys[idx] = _Path(rounded(x[idx]), rounded(y[idx]), rounded(ox[idx]), rounded(oy[idx]),
                              float(paths.target_depth_m), float(paths.obs_depth_m))
        k_by_path = self.k_of_paths(int(paths.ic), list(dict.fromkeys(keys.ravel())))
        out = np.empty(x.shape + (len(self.area.bands),))
        for idx in np.ndindex(x.shape):
            out[idx] = k_by_path[keys[idx]]
        return out

    def k_of_paths(self, ic: int, unique: list[_Path]) -> dict[_Path, np.ndarray]:
        """K of class ``ic`` in every band for each geometry, dB (NaN: land between them)."""
        import time

        start = time.perf_counter()
        area = self.area
        cls = area.classes[ic]
        origin = area.origin
        geometry = {}
        for p in unique:
            lat, lon = local_plane_to_lat_lon(origin.lat_deg, origin.lon_deg, [p.x_m, p.obs_x_m],
                                              [p.y_m, p.obs_y_m])
            geometry[p] = _geodesic(float(lat[0]), float(lon[0]), float(lat[1]), float(lon[1]))
        sources = self._sources(geometry.values())
        prop = area.propagation
        step_m = prop.step_m if prop.step_m is not None else DEFAULT_STEP_M
        runs, where, no_level, path_area = [], {}, set(), {}
        for p, (lat0, lon0, azimuth, distance) in geometry.items():
            area_p = _path_area(area, lat0, lon0, azimuth, distance, p.depth_m)
            path_area[p] = area_p
            radial = area_radials(area_p, behind_m=BEHIND_M, sources=sources)[0]
            if radial.land_range_m is not None and radial.land_range_m < distance:
                no_level.add(p)
                continue
            box = distance * BOX_MARGIN[0] + BOX_MARGIN[1]
            speed = float(origin_speed_of(radial)(p.depth_m))  # the water at the target
            for ib, band in enumerate(area.bands):
                for f in map(freq_key, run_frequencies_hz(area, band)):
                    # the source is the target: the surface at its end is its source pattern
                    pattern = run_pattern(area, cls, band, f, p.depth_m, speed)
                    spec = run_spec(area_p, title=f"tmakit truth {area.name} f={f:.3f} Hz", freq_hz=f,
                                    source_depths_m=(p.depth_m,), receiver_depths_m=(p.obs_depth_m,),
                                    ranges_m=(distance,), pattern=pattern)
                    files = radial_files(area_p, radial, spec, step_m=step_m, box_range_m=box)
                    run = Run(env=files["env"], files=(("bty", files["bty"]), ("ssp", files["ssp"]),
                                                       *spec.side_files().items()),
                              freq_hz=f, source_depth_m=p.depth_m, n_beams=prop.n_beams,
                              pattern_key=pattern.key if pattern is not None else "",
                              timeout_s=run_timeout_s(area, prop.n_beams, 1))
                    runs.append(run)
                    where.setdefault(run.key, []).append((p, ib, f))
        exe = find_bellhop()
        stats = RunStats()
        tl_by_path: dict[tuple[_Path, int], dict[float, np.ndarray]] = {}
        for run, pressure in iter_runs(runs, workers=self.workers, scheduler=self.scheduler,
                                       cache_dir=Path(self.cache_dir) if self.cache_dir is not None else None,
                                       progress=self.progress, exe=str(exe.path), stats=stats):
            for p, ib, f in where[run.key]:
                tl_by_path.setdefault((p, ib), {})[f] = tl_from_pressure(pressure, prop.tl_max_db)
        out = {}
        for p in unique:
            if p in no_level:
                out[p] = np.full(len(area.bands), np.nan)
                continue
            out[p] = np.array([spectral_term_db(cls, band)
                               - float(band_tl_from_runs(path_area[p], cls, band, tl_by_path[(p, ib)])[0, 0])
                               for ib, band in enumerate(area.bands)])
        self.stats.paths += len(unique)
        self.stats.runs += stats.runs_total
        self.stats.cached += stats.runs_reused
        self.stats.bellhop_seconds += stats.bellhop_seconds
        self.stats.wall_seconds += time.perf_counter() - start
        return out

    def _sources(self, geometries) -> WaterSources:
        """The bathymetry and water of the boxes all the paths cross, read once."""
        lats, lons = [], []
        for lat0, lon0, azimuth, distance in geometries:
            pl, po = geodesic_points(lat0, lon0, azimuth, np.linspace(-BEHIND_M, distance, 9))
            lats.append(pl)
            lons.append(po)
        lat, lon = np.concatenate(lats), np.concatenate(lons)
        return WaterSources(bathymetry=load_bathymetry_box(self.area, lat, lon),
                            climatology=load_climatology_box(self.area, lat, lon))


def _geodesic(lat0: float, lon0: float, lat1: float, lon1: float) -> tuple[float, float, float, float]:
    """From a target to an observer: the target's position, the azimuth at it (deg clockwise from
    north, in [0, 360)) and the distance, m (WGS84; at least 1 m)."""
    from pyproj import Geod

    azimuth, _, distance = Geod(ellps="WGS84").inv(lon0, lat0, lon1, lat1)
    return lat0, lon0, float(np.mod(azimuth, 360.0)), max(float(distance), 1.0)


def _path_area(area: Area, lat0: float, lon0: float, azimuth_deg: float, distance_m: float,
               source_depth_m: float) -> Area:
    """The one-radial area of a path: ``[origin]`` at the target, the radial toward the observer,
    one range (the observer's), the source's depth as the area's observer depth (the radial's
    checks are on the water at its origin)."""
    azimuth = round(azimuth_deg, 6) % 360.0
    return dataclasses.replace(
        area, origin=Origin(lat_deg=lat0, lon_deg=lon0), latitude_deg=lat0, longitude_deg=lon0,
        bearings=Bearings(listed_deg=(azimuth,)), atlas=None,
        grid=GridSpec(range_max_m=distance_m, range_step_m=distance_m, depth_step_m=area.grid.depth_step_m),
        observer=Observer(depth_m=max(source_depth_m, 0.1)))


__all__ = ["BellhopTruth", "POSITION_STEP_M", "TruthStats"]
