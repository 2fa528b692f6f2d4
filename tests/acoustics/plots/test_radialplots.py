"""Figures of a bearing-dependent grid, on a small real shelf-break grid built by BELLHOP.

The figures' data are read back from their artists (by gid) and compared with the grid, and the
detection range with independent computations: straight from the grid on a radial, and through
the trackers' tables (acoustics.grid.face) between radials.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

import acoustics
import envdata
from acoustics.detection import band_snr_db, indicator_snr, k_needed_db
from acoustics.grid.detectionmap import detection_map
from acoustics.grid.lookup import at_bearings, bearing_weights
from acoustics.plots.bathymetry import find_bathymetry, load_around_origin
from acoustics.plots.bottomplot import bottom_figure
from acoustics.plots.depthplot import depth_k_figure
from acoustics.plots.gridplots import PlotRequest, plot_grid, plot_paths
from acoustics.plots.mapplot import map_figure
from acoustics.plots.radialplots import bearing_plot_paths, plot_bearing_grid
from acoustics.plots.sectionplot import section_figure
from acoustics.plots.what import What
from envdata.errors import InputError

pytestmark = pytest.mark.bellhop

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
#: A small array: at the area's 42 dB every class is heard to the grid's end wherever it has K,
#: and a detection map would only show where K ends; at 2 dB the bands part.
SMALL_DI_DB = 2.0


def small_shelf_area_file(folder: Path, *, directivity_index_db: float = SMALL_DI_DB) -> Path:
    """The built-in shelf break with four radials to 24 km (north meets the coast at ~22 km),
    data paths made absolute, and a small array."""
    builtin = envdata.area_path("shelf-break")
    text = builtin.read_text()
    text = text.replace('"data/', f'"{builtin.parent}/data/')
    text = text.replace("step_deg = 30.0", "bearing_deg = [0.0, 90.0, 180.0, 270.0]")
    text = text.replace("range_max_m = 30000.0", "range_max_m = 24000.0")
    text = text.replace("directivity_index_db = 42.0", f"directivity_index_db = {directivity_index_db}")
    assert "bearing_deg = [0.0" in text and f"directivity_index_db = {directivity_index_db}" in text
    path = folder / "shelf-small.toml"
    path.write_text(text)
    return path


def png_size(path: Path) -> tuple[int, int]:
    """Width and height from a PNG's IHDR chunk, after checking the signature."""
    head = path.read_bytes()[:24]
    assert head[:8] == PNG_SIGNATURE and head[12:16] == b"IHDR"
    return int.from_bytes(head[16:20], "big"), int.from_bytes(head[20:24], "big")


@pytest.fixture(scope="module")
def shelf_grid_file(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("shelf")
    out = folder / "shelf-small.nc"
    acoustics.build_grid_file(envdata.load_area(small_shelf_area_file(folder)), out, workers=2)
    return out


@pytest.fixture(scope="module")
def shelf(shelf_grid_file):
    return acoustics.open_tables(shelf_grid_file)


def by_gid(fig, gid: str):
    found = [a for ax in fig.axes for a in ax.get_children() if a.get_gid() == gid]
    assert len(found) == 1, (gid, len(found))
    return found[0]


def independent_detection_range_m(shelf, cls_name: str, k_db: np.ndarray) -> float:
    """Detection range from K(band, range) with the area file's own numbers, written out."""
    area = envdata.load_area(envdata.area_path("shelf-break"))  # noise, bands, classes as built
    cls = next(c for c in area.classes if c.name == cls_name)
    best = -math.inf
    for i, band in enumerate(area.bands):
        noise = area.noise.band_level_db(band)
        snr_db = cls.noise_mean_db + k_db[i] - (noise - SMALL_DI_DB)
        q_ind = 10.0 ** (snr_db / 10.0) * math.sqrt((band.high_hz - band.low_hz) * 10.0)
        hit = shelf.dataset["range"].values[np.nan_to_num(q_ind, nan=0.0) >= 5.0]
        best = max(best, hit.max()) if hit.size else best
    return best if math.isfinite(best) else math.nan


def test_the_fixture_grid_is_what_the_tests_need(shelf):
    bottom = shelf.dataset["bottom_depth_m"]
    assert list(shelf.dataset["bearing"].values) == [0.0, 90.0, 180.0, 270.0]
    assert np.isnan(bottom.sel(bearing=0.0).values[-1])            # the coast to the north
    assert np.isfinite(bottom.sel(bearing=180.0).values).all()
    # the small array makes detection end inside the grid (24 km) on some bearings, not only at
    # land (20.4 km at the nearest, measured at 78fa277; under 20 km before the sea surface at the
    # target's end, README "The house")
    sw = detection_map(shelf, "SW", [90.0, 180.0, 270.0])
    assert np.nanmin(sw.range_m) < 22_000.0
    assert np.ptp(sw.band_range_m[:, 1]) > 5_000.0  # seaward, the bands' ranges differ


@pytest.mark.parametrize("cls_name, bearing", [("SW", 90.0), ("SW", 180.0), ("NPS", 0.0), ("TV", 270.0)])
def test_the_detection_line_on_a_radial_is_the_independent_detection_range(shelf, cls_name, bearing):
    fig = map_figure(shelf, what="detection")
    line = by_gid(fig, f"detection:{cls_name}")
    theta, r_km = line.get_data()
    at = np.flatnonzero(np.isclose(np.degrees(theta), bearing))[0]
    k = shelf.dataset["k_db"].sel({"class": cls_name, "bearing": bearing}).values   # (band, range)
    expected = independent_detection_range_m(shelf, cls_name, k)
    assert_allclose(r_km[at] * 1000.0, expected, rtol=0, atol=1e-6, equal_nan=True)
    # each band's line is that band alone; the filled outline is the farthest of them
    bands = [by_gid(fig, f"detection:{cls_name}:{b}").get_data()[1][at] for b in shelf.dataset["band"].values]
    assert_allclose(np.nanmax(bands), r_km[at], equal_nan=True)


def test_between_radials_the_detection_range_is_the_trackers(shelf):
    tables = shelf
    sonar = tables.area.sonar
    dm = detection_map(shelf, "SW", [45.0, 135.0, 200.0, 315.0])
    for j, bearing in enumerate(dm.bearing_deg):
        k = tables.k_db(bearing_deg=bearing)[tables.class_index("SW")]          # (M, R)
        snr = 126.02 + k - (tables.noise_band_db - sonar.directivity_index_db)[:, None]
        q = 10.0 ** (snr / 10.0) * np.sqrt(tables.bandwidth_hz[:, None] * sonar.integration_time_s)
        det = np.nan_to_num(q, nan=0.0) >= sonar.detection_threshold
        rr = tables.range_m[det.any(axis=0)]
        assert_allclose(dm.range_m[j], rr.max() if rr.size else np.nan, rtol=0, atol=1e-6, equal_nan=True)


def test_k_needed_is_where_the_indicator_snr_meets_the_threshold():
    # Q = q sqrt(df T) = 5 with df T = 200 * 10: q = 5 / sqrt(2000), 10 lg q = 6.9897 - 16.5051 dB
    need = k_needed_db(100.0, 60.0, 20.0, 200.0, 10.0, 5.0)
    assert_allclose(need, -9.5154 - 100.0 + 60.0 - 20.0, rtol=0, atol=1e-4)
    q_ind = indicator_snr(band_snr_db(need, 100.0, 60.0, 20.0), 200.0, 10.0)
    assert_allclose(q_ind, 5.0, rtol=1e-12)


def test_the_k_map_shows_the_grid_on_each_radial_and_its_interpolation_between(shelf):
    fig = map_figure(shelf, what="k", band="FB2")
    mesh = by_gid(fig, "k:TV")
    values = np.ma.filled(mesh.get_array(), np.nan).reshape(shelf.dataset.sizes["range"], -1)   # (range, bearing)
    bearings = np.unique(np.concatenate([np.arange(0.0, 360.0, 1.0), shelf.dataset["bearing"].values]))
    k = shelf.dataset["k_db"].sel({"class": "TV", "band": "FB2"})
    for b in shelf.dataset["bearing"].values:
        assert_allclose(values[:, np.flatnonzero(bearings == b)[0]], k.sel(bearing=b).values, equal_nan=True)
    # 30 deg past north: 2/3 of radial 0 and 1/3 of radial 90 (NaN where radial 0 is beyond land)
    mixed = (2 * k.sel(bearing=0.0).values + k.sel(bearing=90.0).values) / 3
    assert_allclose(values[:, np.flatnonzero(bearings == 30.0)[0]], mixed, equal_nan=True)
    assert np.isnan(values[-1, np.flatnonzero(bearings == 30.0)[0]])


def test_between_radials_the_interpolation_is_linear_across_north():
    grid = np.array([0.0, 90.0, 180.0, 270.0])
    j0, j1, w1 = bearing_weights(grid, [10.0, 315.0, 359.999, 90.0])
    assert list(j0) == [0, 3, 3, 1] and list(j1) == [1, 0, 0, 2]
    assert_allclose(w1, [10 / 90, 0.5, 89.999 / 90, 0.0])
    values = np.array([[1.0, np.nan], [2.0, 5.0], [3.0, 6.0], [4.0, 7.0]])
    got = at_bearings(values, grid, [315.0, 90.0, 45.0])
    assert_allclose(got, [[2.5, np.nan], [2.0, 5.0], [1.5, np.nan]], equal_nan=True)


def test_the_bottom_figure_draws_every_radial_and_where_it_meets_land(shelf):
    fig = bottom_figure(shelf)
    r_km = shelf.dataset["range"].values / 1000.0
    for b in shelf.dataset["bearing"].values:
        x, y = by_gid(fig, f"bottom:{b:g}").get_data()
        assert_allclose(x, r_km)
        assert_allclose(y, shelf.dataset["bottom_depth_m"].sel(bearing=b).values, equal_nan=True)
    north = shelf.dataset["bottom_depth_m"].sel(bearing=0.0).values
    x, y = by_gid(fig, "land:0").get_data()
    last_wet = np.flatnonzero(np.isfinite(north))[-1]
    assert_allclose([x[0], y[0]], [r_km[last_wet], north[last_wet]])
    assert not [a for ax in fig.axes for a in ax.get_children() if a.get_gid() == "land:180"]


@pytest.mark.parametrize("bearing, radial", [(180.0, 180.0), (200.0, 180.0), (225.0, 180.0),
                                             (226.0, 270.0), (350.0, 0.0), (44.0, 0.0)])
def test_the_section_is_the_nearest_radials_tl_bottom_and_k(shelf, bearing, radial):
    fig = section_figure(shelf, bearing_deg=bearing, cls_name="NPS", band="FB3")
    tl = shelf.dataset["tl_db"].sel({"class": "NPS", "band": "FB3", "bearing": radial})
    field = np.ma.filled(by_gid(fig, "section:tl").get_array(), np.nan).reshape(tl.shape)
    assert_allclose(field, tl.values, equal_nan=True)
    assert_allclose(by_gid(fig, "section:bottom").get_data()[1],
                    shelf.dataset["bottom_depth_m"].sel(bearing=radial).values, equal_nan=True)
    for band in shelf.dataset["band"].values:
        assert_allclose(by_gid(fig, f"section:k:{band}").get_data()[1],
                        shelf.dataset["k_db"].sel({"class": "NPS", "band": band, "bearing": radial}).values,
                        equal_nan=True)
    title = fig.axes[0].get_title()
    assert f"radial {radial:g}\N{DEGREE SIGN}" in title
    assert (f"nearest to {bearing:g}" in title) == (bearing != radial)


def test_the_bathymetry_the_grid_records_is_found_and_read_around_the_origin(shelf, shelf_grid_file):
    choice = find_bathymetry(shelf, grid_path=shelf_grid_file)
    assert choice is not None and choice.matches and choice.how == "as named in the grid"
    box = load_around_origin(choice, 43.0, 5.0, 24_000.0)
    # 24 km is about 0.22 deg of latitude and 0.29 deg of longitude at 43 N
    assert box.lat_deg[0] < 43.0 - 0.2 and box.lat_deg[-1] > 43.0 + 0.2
    assert box.lon_deg[0] < 5.0 - 0.28 and box.lon_deg[-1] > 5.0 + 0.28
    assert_allclose(-box.elevation_at(np.array([43.0]), np.array([5.0])),
                    shelf.dataset["bottom_depth_m"].sel(bearing=0.0).values[0], rtol=0.02)
    fig = map_figure(shelf, what="detection", bathymetry=box, bathymetry_note="test")
    assert len(fig.axes) >= 5  # three polar panels, the lat/lon panel and its colour bar
    assert fig.axes[3].get_xlabel().startswith("longitude")


def test_plot_bearing_grid_writes_all_three_pngs(shelf, tmp_path):
    written = plot_bearing_grid(shelf, tmp_path / "m.png", what="detection", bearing_deg=45.0).files
    assert written == {"map": tmp_path / "m.png", "bottom": tmp_path / "m-bottom.png",
                       "section": tmp_path / "m-section.png"}
    for path in written.values():
        w, h = png_size(path)
        assert w >= 1000 and h >= 500
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m-bottom.png", "m-section.png", "m.png"]


def test_one_unwritable_output_leaves_the_others_unwritten(shelf, tmp_path):
    (tmp_path / "m-bottom.png").mkdir()  # the bottom plot cannot go there
    with pytest.raises(OSError):
        plot_bearing_grid(shelf, tmp_path / "m.png")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m-bottom.png"]


def test_an_existing_map_is_kept_when_the_set_fails(shelf, tmp_path):
    old = tmp_path / "m.png"
    old.write_bytes(PNG_SIGNATURE + b"old")
    (tmp_path / "m-section.png").mkdir()
    with pytest.raises(OSError):
        plot_bearing_grid(shelf, old, bearing_deg=10.0)
    assert old.read_bytes() == PNG_SIGNATURE + b"old"
    assert not (tmp_path / "m-bottom.png").exists()


@pytest.mark.parametrize("bearing, radial", [(200.0, 180.0), (226.0, 270.0), (350.0, 0.0), (None, 0.0)])
def test_the_depth_figure_is_k_at_every_target_depth_on_the_nearest_radial(shelf, tmp_path, bearing, radial):
    request = PlotRequest(what=What.DEPTH, cls_name="SW", band="FB2", bearing_deg=bearing)
    out = tmp_path / "depth.png"
    assert plot_paths(shelf, out, request) == {"depth": out}
    written = plot_grid(shelf, out, request)
    assert written.files == {"depth": out} and png_size(out)[0] > 500
    fig = depth_k_figure(shelf, cls_name="SW", band="FB2", bearing_deg=bearing)
    # independently of the face: K = S - TL between the observer and a point at each depth
    # (eq. 13; the bearing-dependent grid's tl_db is from the observer), the grid read with xarray
    ic, ib = shelf.class_index("SW"), shelf.band_index("FB2")
    tl = shelf.dataset["tl_db"].sel({"class": "SW", "band": "FB2", "bearing": radial})
    expected = shelf.spectral_db(ic, ib) - tl.transpose("depth", "range").values
    shown = np.ma.filled(np.asarray(by_gid(fig, "depth:k").get_array(), dtype=float), np.nan)
    # TL is float32 in the grid: K rounded to float32 on the face (some 4e-6 dB at 60 dB)
    assert_allclose(shown.reshape(expected.shape), expected, rtol=0, atol=1e-5, equal_nan=True)
    assert np.isnan(shown).any()  # below the bottom: no K, drawn blank
    assert by_gid(fig, "depth:table").get_ydata()[0] == 6.0  # SW's tables are at 6 m
    lo, hi = shelf.target_depth_span_m(ic)                     # no depth_range_m: the water
    assert (by_gid(fig, "depth:span:min").get_ydata()[0], by_gid(fig, "depth:span:max").get_ydata()[0]) == (lo, hi)
    assert f"radial {radial:g}\N{DEGREE SIGN}" in fig.axes[0].get_title()


@pytest.mark.parametrize("request_, match", [
    (PlotRequest(what=What.DEPTH, bearing_deg=360.0), r"bearing 360 deg: must be in \[0, 360\)"),
    (PlotRequest(what=What.DEPTH, band="FB9"), r"band 'FB9' is not a band of the grid"),
    (PlotRequest(what=What.DEPTH, bathymetry=Path("relief.nc")), "the figure of K against target depth has no map"),
])
def test_bad_depth_figure_options_write_nothing(shelf, tmp_path, request_, match):
    with pytest.raises(InputError, match=match):
        plot_grid(shelf, tmp_path / "d.png", request_)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("kwargs, match", [
    ({"cls_name": "SUB"}, r"class 'SUB' is not a class of the grid \(NPS, SW, TV\)"),
    ({"band": "FB9"}, r"band 'FB9' is not a band of the grid \(FB1, FB2, FB3\)"),
    ({"bearing_deg": 360.0}, r"bearing 360 deg: must be in \[0, 360\)"),
    ({"bearing_deg": -0.5}, r"bearing -0.5 deg: must be in \[0, 360\)"),
    ({"bearing_deg": math.nan}, r"bearing nan deg: must be in \[0, 360\)"),
])
def test_bad_options_are_input_errors_and_write_nothing(shelf, tmp_path, kwargs, match):
    with pytest.raises(InputError, match=match):
        plot_bearing_grid(shelf, tmp_path / "m.png", **kwargs)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("request_, said", [
    (PlotRequest(bearing_deg=10.0), "a section's bearing"), (PlotRequest(band="FB1"), "a map's band"),
    (PlotRequest(what=What.K), "a map"), (PlotRequest(bathymetry=Path("relief.nc")), "a bathymetry file")])
def test_a_flat_grid_refuses_what_only_bearing_grids_draw(tiny_grid, tmp_path, request_, said):
    with pytest.raises(InputError, match=f"{said}.* is for a bearing-dependent grid"):
        plot_grid(acoustics.open_tables(tiny_grid), tmp_path / "m.png", request_)
    assert list(tmp_path.iterdir()) == []


def test_the_plots_follow_the_grids_geometry(tiny_grid, shelf, tmp_path):
    flat = acoustics.open_tables(tiny_grid)
    assert plot_paths(flat, tmp_path / "f.png", PlotRequest()) == {"plot": tmp_path / "f.png"}
    assert set(plot_paths(shelf, tmp_path / "m.png", PlotRequest(bearing_deg=3.0))) == {"map", "bottom", "section"}
    written = plot_grid(flat, tmp_path / "f.png", PlotRequest(cls_name="SHIP"))
    assert written.files == {"plot": tmp_path / "f.png"} and png_size(tmp_path / "f.png")[0] > 500


def test_the_plot_paths_sit_beside_the_map():
    assert bearing_plot_paths(Path("out/a.b.png"), section=True) == {
        "map": Path("out/a.b.png"), "bottom": Path("out/a.b-bottom.png"), "section": Path("out/a.b-section.png")}
    assert bearing_plot_paths("map") == {"map": Path("map"), "bottom": Path("map-bottom.png")}


def test_one_radial_over_a_flat_bottom_plots_too(tiny_area, tmp_path):
    """No contours to draw, no land, one row in the range-bearing image (Urick: no BELLHOP)."""
    doc = tiny_area.to_dict()
    doc["origin"] = {"lat_deg": 43.0, "lon_deg": 5.0}
    doc["area"] = {**doc["area"], "latitude_deg": 43.0, "longitude_deg": 5.0}
    doc["bearings"] = {"bearing_deg": [30.0]}
    grid = acoustics.open_tables(acoustics.build_grid(envdata.parse_area(doc, "one-radial"), model="urick"))
    written = plot_bearing_grid(grid, tmp_path / "one.png", what="detection", bearing_deg=200.0).files
    assert all(png_size(p)[0] > 1000 for p in written.values())
    fig = bottom_figure(grid)
    image = fig.axes[1].collections[0]  # the range-bearing image: one row, the water depth
    assert_allclose(np.asarray(image.get_array()).ravel(), tiny_area.water.depth_m)
    assert np.ptp(image.get_coordinates()[..., 1]) > 0.0  # the row has a height: it shows
    dm = detection_map(grid, "SHIP", [30.0, 210.0])
    assert dm.range_m[0] == dm.range_m[1]  # one radial serves every bearing
