"""BELLHOP3D's Nx2D mode: the writers, the multi-bearing .shd reader, and real runs against the 2-D route."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

import envdata
from acoustics.bellhop.envfile import RunSpec
from acoustics.bellhop.exe import find_bellhop, find_bellhop3d
from acoustics.bellhop.runner import run_env
from acoustics.bellhop.shdfile import tl_from_pressure
from acoustics.builder.radial import bottom_on_grid_m, depth_axis_m, plan_radial_runs
from acoustics.builder.runs import execute_runs
from acoustics.errors import BellhopError
from acoustics.nx2d.box3d import BoxEnvironment, box_positions, sample_box
from acoustics.nx2d.env3d import bellhop3d_bearings, coverage_m, nx2d_files
from acoustics.nx2d.route import box_range_m, nx2d_fields, plan_nx2d_runs, ray_step_m, sample_area_box
from acoustics.nx2d.shd3d import read_shd3d
from envdata.area import Absorption
from envdata.radials import area_radials, geodesic_points
from tests.conftest import DATA
from tests.fixtures.isovelocity import isovelocity_doc

pytestmark = pytest.mark.bellhop

HALF_M = 6000.0  # the tiny boxes' half width
STEP_M = 10.0


def _iso_area() -> envdata.Area:
    """Isovelocity 1000 m over an impedance-matched bottom, with an origin (for the box)."""
    doc = isovelocity_doc("iso3d", depth_m=1000.0, observer_m=500.0, freq_hz=100.0, range_max_m=4000.0,
                          range_step_m=500.0, depth_step_m=100.0)
    doc["area"].update(latitude_deg=43.0, longitude_deg=5.0)
    doc.update(origin={"lat_deg": 43.0, "lon_deg": 5.0}, bearings={"bearing_deg": [0.0, 60.0, 90.0, 200.0]},
               propagation={"step_m": STEP_M, "n_beams": 200, "angle_min_deg": -20.0, "angle_max_deg": 20.0,
                            "absorption": "none"})
    return envdata.parse_area(doc, "iso3d")


def _iso_box(ridge_east: bool = False) -> BoxEnvironment:
    """The isovelocity water on a box; with ``ridge_east`` a ridge 100 m deep along the +x axis
    from x = 2 km (|y| <= 1 km) blocks the eastward radial at mid-depth."""
    x = np.arange(-HALF_M, HALF_M + 1.0, 250.0)
    bottom = np.full((x.size, x.size), 1000.0)
    if ridge_east:
        bottom[np.ix_(np.abs(x) <= 1000.0, x >= 2000.0)] = 100.0
    return BoxEnvironment(origin_lat_deg=43.0, origin_lon_deg=5.0, x_m=x, y_m=x, bottom_depth_m=bottom,
                          ssp_x_m=[-HALF_M, HALF_M], ssp_y_m=[-HALF_M, HALF_M], ssp_depth_m=[0.0, 1000.0],
                          speed_mps=np.full((2, 2, 2), 1500.0))


def _run(area, box, bearings, ranges_m, receivers_m, tmp_path):
    spec = RunSpec(title="nx2d test", freq_hz=100.0, source_depth_m=(500.0,), receiver_depth_m=tuple(receivers_m),
                   range_m=tuple(ranges_m), n_beams=200, angle_min_deg=-20.0, angle_max_deg=20.0,
                   absorption=Absorption.NONE)
    files = nx2d_files(area, box, spec, bearing_deg=bearings, step_m=STEP_M, box_range_m=4500.0)
    run_env(files["env"], exe=find_bellhop3d().path, keep_dir=tmp_path,
            files={"bty": files["bty"], "ssp": files["ssp"]})
    return tmp_path / "tmakit.shd", files


def test_bearings_turn_from_clockwise_north_to_counter_clockwise_east():
    theta, index = bellhop3d_bearings([0.0, 60.0, 90.0, 200.0])
    assert_allclose(theta, [0.0, 30.0, 90.0, 250.0])  # sorted, as BELLHOP3D keeps them
    assert_allclose(theta[index], [90.0, 30.0, 0.0, 250.0])  # north is +y, east is +x
    with pytest.raises(ValueError, match="distinct directions"):
        bellhop3d_bearings([10.0, 370.0])


def test_reader_gives_every_bearing_of_a_real_run_near_spherical_spreading(tmp_path):
    """Direct path only (beams within +-20 deg never reach the surface or bottom 500 m away
    within 1 km): TL = 20 lg r, 60 dB at 1 km, on every bearing."""
    ranges = [200.0, 500.0, 1000.0]
    path, _ = _run(_iso_area(), _iso_box(), [0.0, 60.0, 90.0, 200.0], ranges, [500.0, 520.0], tmp_path)
    shade = read_shd3d(path)
    assert shade.pressure.shape == (4, 1, 2, 3)
    assert_allclose(shade.bearing_deg, [0.0, 30.0, 90.0, 250.0])
    assert_allclose(shade.range_m, ranges)  # metres in the 2022 layout
    assert_allclose(shade.receiver_depth_m, [500.0, 520.0])
    assert_allclose(shade.source_depth_m, [500.0])
    assert shade.freq_hz == 100.0 and shade.source_x_m == 0.0 and shade.source_y_m == 0.0
    tl = tl_from_pressure(shade.pressure[:, 0, 0, :], 200.0)
    assert_allclose(tl, np.broadcast_to(20.0 * np.log10(ranges), tl.shape), rtol=0, atol=0.5)


def test_bearings_come_back_in_the_areas_order(tmp_path):
    """A ridge east of the origin leaves only the eastward radial (bearing 90) without sound at
    mid-depth beyond it; after the conversion that radial is the third of the area's four."""
    bearings = [0.0, 60.0, 90.0, 200.0]
    ranges = [1000.0, 3000.0, 3500.0]
    path, _ = _run(_iso_area(), _iso_box(ridge_east=True), bearings, ranges, [500.0], tmp_path)
    shade = read_shd3d(path)
    _, index = bellhop3d_bearings(bearings)
    tl = tl_from_pressure(shade.pressure[index, 0, 0, :], 200.0)  # (bearing in the area's order, range)
    assert_allclose(tl[:, 0], 60.0, rtol=0, atol=0.5)  # before the ridge all alike
    beyond = tl[:, 1:]
    assert np.all(beyond[2] > 150.0)  # east: blocked
    assert np.all(np.delete(beyond, 2, axis=0) < 75.0)  # the others: open water


def test_writers_refuse_a_box_smaller_than_the_rays_box():
    box = _iso_box()
    spec = RunSpec(title="t", freq_hz=100.0, source_depth_m=(500.0,), receiver_depth_m=(500.0,),
                   range_m=(1000.0,), n_beams=10)
    need = coverage_m(5500.0, STEP_M)
    assert need > HALF_M
    with pytest.raises(ValueError, match=r"bathymetry grid reaches 6000 m from the origin, less than"):
        nx2d_files(_iso_area(), box, spec, bearing_deg=[0.0], step_m=STEP_M, box_range_m=5500.0)


def _numbers(line: str) -> np.ndarray:
    return np.array([float(v) for v in line.replace("/", " ").split()])


def test_the_shelf_break_box_covers_the_rays_box_with_bathymetry_and_sound_speed():
    area = envdata.load_area("shelf-break")
    env = sample_area_box(area)
    box = box_range_m(area)
    need = coverage_m(box, ray_step_m(area))
    assert box > area.grid.range_max_m
    assert env.bathymetry_half_width_m() >= need and env.ssp_half_width_m() >= need
    # the bottom is real bathymetry: the shelf and the coast north, the basin south, land as 1 m
    assert env.bottom_depth_m.min() == pytest.approx(1.0) and env.bottom_depth_m.max() > 2000.0
    assert env.ssp_depth_m[-1] == pytest.approx(env.bottom_depth_m.max())
    # the written files say the same: .bty and .ssp extents (km) beyond the .env's ray box (km)
    receivers = depth_axis_m(area, area_radials(area))
    item = plan_nx2d_runs(area, env, receivers)[0]
    files = dict(item.run.files)
    box_line = _numbers(item.run.env.strip().splitlines()[-1])  # step (m), box x, y (km), box z (m)
    assert box_line[0] == ray_step_m(area) and box_line[1] == box_line[2] == pytest.approx(box / 1000.0)
    bty = files["bty"].splitlines()
    ssp = files["ssp"].splitlines()
    assert bty[0] == "'R'"
    for xs in (_numbers(bty[2]), _numbers(bty[4]), _numbers(ssp[1]), _numbers(ssp[3])):
        assert xs[0] < -box_line[1] and xs[-1] > box_line[1]
    assert len(bty) == 5 + int(bty[3]) and len(_numbers(bty[5])) == int(bty[1])
    nz, ny = int(ssp[4]), int(ssp[2])
    assert len(ssp) == 6 + nz * ny
    assert box_line[3] == pytest.approx(1.01 * _numbers(ssp[5])[-1] + 1.0)  # rays stop below the deepest bottom
    # the .env's own profile has exactly the .ssp's depths (BELLHOP3D takes attenuation from it)
    env_depths = [float(line.split()[0]) for line in item.run.env.splitlines()[5:5 + nz]]
    assert_allclose(env_depths, _numbers(ssp[5]))


def test_box_radials_are_the_geodesics():
    """On the azimuthal equidistant box a straight radial passes over the geodesic's points."""
    area = envdata.load_area("shelf-break")
    for bearing in (0.0, 30.0, 135.0, 250.0):
        lat, lon = geodesic_points(43.0, 5.0, bearing, [30000.0])
        x = 30000.0 * np.sin(np.radians(bearing))
        y = 30000.0 * np.cos(np.radians(bearing))
        blat, blon = box_positions(area, [x], [y])
        assert_allclose([blat[0], blon[0]], [lat[0], lon[0]], rtol=0, atol=1e-8)  # < 1 mm


def test_sample_box_refuses_a_box_beyond_the_bathymetry_file():
    area = envdata.load_area("shelf-break")
    with pytest.raises(envdata.AreaError, match=r"leaves the bathymetry file at x = "):
        sample_box(area, 60000.0)


def _flat_area_with_origin() -> envdata.Area:
    """The tiny Munk area, flat and one profile, with an origin and four radials."""
    doc = envdata.load_area(DATA / "tiny-munk.toml").to_dict()
    doc["origin"] = {"lat_deg": 43.0, "lon_deg": 5.0}
    doc["bearings"] = {"bearing_deg": [0.0, 45.0, 100.0, 270.0]}
    doc["area"] = {**doc["area"], "latitude_deg": 43.0, "longitude_deg": 5.0}
    doc["propagation"] = {**doc["propagation"], "step_m": 10.0}
    return envdata.parse_area(doc, "flat-with-origin")


def _two_routes(area, **options):
    radials = area_radials(area)
    depth = depth_axis_m(area, radials)
    receivers = np.unique(np.concatenate([depth, [c.depth_m for c in area.classes]]))
    runs, where = plan_radial_runs(area, radials, receivers)
    two_d = execute_runs(runs, workers=2)
    nx2d = nx2d_fields(area, receivers, workers=2, **options)
    return radials, receivers, runs, where, two_d, nx2d


def test_nx2d_reproduces_the_2d_runs_on_a_flat_area():
    area = _flat_area_with_origin()
    _, _, _, where, two_d, nx2d = _two_routes(area, bearing_groups=2)
    assert set(nx2d) == {f for _, f in where.values()}
    for key, (j, f) in where.items():
        a = tl_from_pressure(two_d[key], 200.0)
        b = tl_from_pressure(nx2d[f][j], 200.0)
        audible = a < 120.0
        assert audible.mean() > 0.5
        assert np.median(np.abs(a - b)[audible]) < 0.01 and np.abs(a - b)[audible].max() < 0.5, (j, f)


def test_nx2d_follows_the_2d_runs_over_real_bathymetry():
    """The shelf break, three radials to 8 km: landward, along the slope, seaward."""
    area = envdata.load_area("shelf-break")
    doc = area.to_dict()
    doc["bearings"] = {"bearing_deg": [0.0, 90.0, 180.0]}
    doc["grid"]["range_max_m"] = 8000.0
    doc["bands"] = doc["bands"][:1]
    area = envdata.parse_area(doc, "shelf-short", folder=envdata.area_path("shelf-break").parent)
    radials, receivers, _, where, two_d, nx2d = _two_routes(area)
    for key, (j, f) in where.items():
        a = tl_from_pressure(two_d[key], 200.0)
        b = tl_from_pressure(nx2d[f][j], 200.0)
        wet = receivers[:, None] <= np.nan_to_num(bottom_on_grid_m(area, radials[j]), nan=-1.0)[None, :]
        cells = wet & (a < 120.0)
        d = np.abs(a - b)[cells]
        assert cells.sum() > 1000
        assert np.median(d) < 0.1 and np.percentile(d, 90) < 1.0, radials[j].bearing_deg


def test_a_header_inconsistent_multi_bearing_shd_is_a_bellhop_error(tmp_path):
    path, _ = _run(_iso_area(), _iso_box(), [0.0, 90.0, 180.0], [500.0, 1000.0], [500.0], tmp_path)
    good = path.read_bytes()
    assert read_shd3d(path).pressure.shape == (3, 1, 1, 2)
    lrecl = int(np.frombuffer(good[:4], "<i4")[0])
    header = 2 * 4 * lrecl  # record 3: Nfreq, Ntheta, NSx, NSy, NSz, NRz, NRr

    def edited(field: int, value: int):
        raw = bytearray(good)
        raw[header + 4 * field:header + 4 * field + 4] = np.int32(value).tobytes()
        bad = tmp_path / f"bad{field}.shd"
        bad.write_bytes(bytes(raw))
        return bad

    with pytest.raises(BellhopError, match=r"shade file is truncated: \d+ bytes, the header's counts "
                                           r"\(Nfreq = 1, Ntheta = 30,"):
        read_shd3d(edited(1, 30))  # ten times the bearings the file holds
    with pytest.raises(BellhopError, match=r"header is inconsistent: NSz = 0"):
        read_shd3d(edited(4, 0))
    with pytest.raises(BellhopError, match=r"header is inconsistent: Ntheta = 100000 does not fit a record"):
        read_shd3d(edited(1, 100_000))
    bearings = bytearray(good)
    bearings[4 * 4 * lrecl:4 * 4 * lrecl + 4] = np.float32(500.0).tobytes()  # first bearing past the last
    (tmp_path / "order.shd").write_bytes(bytes(bearings))
    with pytest.raises(BellhopError, match=r"bearings \[500.0, 90.0, 270.0\] deg are not in increasing order"):
        read_shd3d(tmp_path / "order.shd")
    (tmp_path / "short.shd").write_bytes(good[:-10])
    with pytest.raises(BellhopError, match=r"shade file is truncated"):
        read_shd3d(tmp_path / "short.shd")


def test_bellhop3d_failure_reports_its_own_message(tmp_path):
    box = _iso_box()
    spec = RunSpec(title="t", freq_hz=100.0, source_depth_m=(500.0,), receiver_depth_m=(500.0,),
                   range_m=(1000.0,), n_beams=10)
    files = nx2d_files(_iso_area(), box, spec, bearing_deg=[0.0], step_m=STEP_M, box_range_m=4000.0)
    # an 'H' sound speed smaller than the rays' box is fatal (the writers never produce one)
    ssp = files["ssp"].replace(f"{-HALF_M / 1000:g} {HALF_M / 1000:g}", "-0.5 0.5")
    assert ssp != files["ssp"]
    with pytest.raises(BellhopError, match=r"ray is outside the box where the soundspeed is defined"):
        run_env(files["env"], exe=find_bellhop3d().path, files={"bty": files["bty"], "ssp": ssp})


def test_bellhop3d_is_installed_beside_bellhop():
    exe3d = find_bellhop3d()
    assert exe3d.path.name == "bellhop3d.exe" and exe3d.path.parent == find_bellhop().path.parent
    assert exe3d.version.startswith("aubellhop ") and len(exe3d.sha256) == 64
