"""Bearing-dependent grids (N x 2D) built by the real BELLHOP along radials."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

import acoustics
import envdata
from tests.conftest import DATA

pytestmark = pytest.mark.bellhop


def _flat_area_with_origin() -> envdata.Area:
    """The tiny Munk area, flat and one profile, with an origin and three radials."""
    tiny = envdata.load_area(DATA / "tiny-munk.toml")
    doc = tiny.to_dict()
    doc["origin"] = {"lat_deg": 43.0, "lon_deg": 5.0}
    doc["bearings"] = {"step_deg": 120.0}
    doc["area"] = {**doc["area"], "latitude_deg": 43.0, "longitude_deg": 5.0}
    doc["propagation"] = {**doc["propagation"], "step_m": 10.0}
    return envdata.parse_area(doc, "flat-with-origin")


def test_a_flat_area_with_an_origin_reproduces_the_isotropic_grid_at_every_bearing():
    area = _flat_area_with_origin()
    radial = acoustics.build_grid(area, workers=2)
    assert radial["tl_db"].attrs["fixed_end"] == "observer"
    assert list(radial["bearing"].values) == [0.0, 120.0, 240.0]
    # the same TL the usual way: classes radiating from the observer's depth, no origin
    doc = area.to_dict()
    del doc["origin"], doc["bearings"]
    for cls in doc["classes"]:
        cls["depth_m"] = area.observer.depth_m
    flat = acoustics.build_grid(envdata.parse_area(doc, "flat"), workers=2)
    assert flat["tl_db"].attrs["fixed_end"] == "source"
    depth = flat["depth"].values
    # rows within the surface's reach (5 wavelengths at the lowest band's low edge: 77 m at
    # 100 Hz) come from the arrivals run with the surface at the target's end, which the flat
    # grid's source at 100 m has not
    reach = 5.0 * 1548.0 / min(band.low_hz for band in area.bands)
    deep = np.broadcast_to(depth[None, None, :, None] >= reach, (2, 2, depth.size, 50))
    for bearing in radial["bearing"].values:
        a = radial["tl_db"].sel(bearing=bearing, depth=depth).values
        b = flat["tl_db"].values
        audible = b < 150.0  # away from the deep shadows the caps would compare
        assert np.abs(a - b)[audible & deep].max() < 0.1, bearing
        # the 0 m row holds the loss 1 m down, with the surface's dipole: far lossier than the flat
        # grid's incoherent receiver at the surface itself
        assert np.median((a - b)[:, :, 0][audible[:, :, 0]]) > 3.0
    # the water is flat: the bottom is the water depth on every radial, and nothing is NaN above it
    assert_allclose(radial["bottom_depth_m"].values, area.water.depth_m)
    assert np.isfinite(radial["k_db"].values).all()


def test_the_shelf_break_grid_file(tmp_path, capsys):
    from tools import cli

    out = tmp_path / "shelf.nc"
    area_file = tmp_path / "shelf.toml"
    text = (envdata.area_path("shelf-break")).read_text()
    folder = envdata.area_path("shelf-break").parent
    text = text.replace('"data/', f'"{folder}/data/')
    # three radials to 12 km keep the test short: toward land (0), along the slope (90), seaward (180)
    text = text.replace("step_deg = 30.0", "bearing_deg = [0.0, 90.0, 180.0]")
    text = text.replace("range_max_m = 30000.0", "range_max_m = 24000.0")
    area_file.write_text(text)
    assert cli.main(["grids", "build", str(area_file), "--out", str(out), "--workers", "2"]) == 0
    capsys.readouterr()
    grid = acoustics.open_tables(out).dataset
    assert grid.sizes["bearing"] == 3 and grid["tl_db"].dims == ("class", "band", "bearing", "depth", "range")
    bottom = grid["bottom_depth_m"]
    # toward land the radial ends at the coast; seaward the water deepens beyond the slope
    north, south = bottom.sel(bearing=0.0).values, bottom.sel(bearing=180.0).values
    assert np.isnan(north[-1]) and np.isfinite(north[0])
    assert np.nanmax(south) > 1500.0 and np.nanmax(north) < 600.0
    # below the bottom and beyond land the tables hold nothing
    tl = grid["tl_db"].sel({"class": "SW", "band": "FB1", "bearing": 0.0})
    below = grid["depth"].values[:, None] > north[None, :]
    assert np.isnan(tl.values[below]).all() and np.isfinite(tl.values[~below & np.isfinite(north)[None, :]]).all()
    # a submarine at 200 m has no K where the shelf is shallower than 200 m
    k_nps = grid["k_db"].sel({"class": "NPS", "band": "FB1", "bearing": 0.0}).values
    assert np.isnan(k_nps[north < 200.0]).all() and np.isfinite(k_nps[north > 210.0]).all()
    files = grid.attrs["input_files"]
    assert "shelf-break_gebco_15s.nc" in files and "sha256" in files
    assert grid.attrs["source_hash"] == acoustics.expected_source_hash(envdata.load_area(area_file))
