"""Atlases built by the real BELLHOP into a real Zarr store: content, resume, damage, refusals,
interpolation between positions, and a Dask cluster of worker processes losing a worker."""

from __future__ import annotations

import json
import math
import os
import shutil
import signal
import threading
import time

import numpy as np
import pytest

import acoustics
from acoustics.builder.atlas import build_atlas_file
from acoustics.grid.atlas.format import AtlasFileError
from acoustics.grid.atlas.sample import values_at
from acoustics.grid.atlas.store import open_store
from acoustics.grid.atlas.weights import WATER_DEPTH_RATIO
from acoustics.grid.radialtables import RadialTables
from envdata.atlasarea import table_area
from envdata.bathymetry import open_bathymetry
from envdata.errors import InputError
from envdata.geometry import lat_lon_to_local_plane
from tests.acoustics.atlas.atlasarea import load_atlas_area

pytestmark = pytest.mark.bellhop


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    folder = tmp_path_factory.mktemp("atlas")
    area = load_atlas_area(folder)
    out = folder / "a.zarr"
    info = build_atlas_file(area, out, workers=2)
    return area, out, info


def _tables(path):
    atlas = open_store(path)
    return {(m, o): atlas.slab(m, o) for m in range(atlas.months.size) for o in range(atlas.lat_deg.size)}


def _same(a, b):
    return all(np.array_equal(x, y, equal_nan=True) for key in a for x, y in zip(a[key], b[key]))


def test_each_table_is_exactly_the_grid_of_its_position_and_month(built):
    area, out, info = built
    # 3 x 3 lattice, its northern row on the shelf under the 100 m observer: 6 positions x 2 months
    assert info["positions"] == 6 and len(info["left_out"]) == 3 and info["tables"] == 12
    # 4 radials x 1 run frequency per table, each a TL run and the arrivals run of the surface at
    # the target's end (its near-surface rows)
    assert info["runs"] == 12 * 4 * 2
    atlas = open_store(out)
    assert atlas.done.all()
    table = atlas.sel(month=2, origin=4)
    assert isinstance(table, RadialTables)
    grid = acoustics.build_grid(table_area(area, 2, atlas.lat_deg[4], atlas.lon_deg[4]), workers=2)
    depth = atlas.depth_m[atlas.depth_m <= grid["depth"].values[-1]]
    tl, k, bottom = atlas.slab(0, 4)
    want = grid["tl_db"].sel(depth=depth).transpose("class", "band", "bearing", "depth", "range").values
    # the same BELLHOP runs on the same inputs: bit for bit (the atlas's 50 m axis is a subset of
    # the grid's 25 m one), NaN below the bottom in the same cells
    assert np.array_equal(tl[:, :, :, :depth.size], want, equal_nan=True)
    assert np.isnan(tl[:, :, :, depth.size:]).all()
    assert np.array_equal(k, grid["k_db"].values, equal_nan=True)
    assert np.array_equal(bottom, grid["bottom_depth_m"].values, equal_nan=True)
    # February's water is not August's
    assert np.nanmax(np.abs(atlas.slab(0, 4)[1] - atlas.slab(1, 4)[1])) > 0.1


def test_values_between_positions_are_weighted_in_db_and_outside_is_an_error(built):
    _, out, _ = built
    atlas = open_store(out)
    kw = dict(month=8, cls_name="TV", band_name="FB2", bearing_deg=90.0, range_m=5000.0)
    k, tl = values_at(atlas, lat_deg=atlas.lat_deg, lon_deg=atlas.lon_deg, **kw)
    for o in range(atlas.lat_deg.size):  # at a position: its own table (k_db at 90 deg, 5 km)
        assert k[o] == pytest.approx(atlas.slab(1, o)[1][0, 0, 1, 24], abs=1e-9)
    # midway between two nodes of a row, with the bilinear weights alone: the mean of their
    # values in dB (tc = 0.5)
    mid_lon = 0.5 * (atlas.lon_deg[0] + atlas.lon_deg[1])
    atlas.water_depth_ratio = None
    km, tlm = values_at(atlas, lat_deg=[atlas.lat_deg[0]], lon_deg=[mid_lon], **kw)
    assert km[0] == pytest.approx(0.5 * (k[0] + k[1]), abs=1e-9)
    assert tlm[0] == pytest.approx(0.5 * (tl[0] + tl[1]), abs=1e-6)
    # as the atlas weighs by default, each weight tempered by the water; midway between a node on
    # the slope (position 1, ~925 m) and the one north of it on the shelf edge (position 4, ~190 m):
    # the depth there read along the two nodes' radials (north from one, south from the other:
    # both reach it) is the relief's, and the node whose water is nearer it (in ratio) weighs more
    atlas.water_depth_ratio = WATER_DEPTH_RATIO
    area, _, _ = built
    lat, lon = np.array([0.5 * (atlas.lat_deg[1] + atlas.lat_deg[4])]), atlas.lon_deg[[1]]
    with open_bathymetry(area.water.bathymetry) as relief:
        h_mid = float(-relief.load_box(lat, lon).elevation_at(lat, lon)[0])
    x, y = lat_lon_to_local_plane(area.origin.lat_deg, area.origin.lon_deg, lat, lon)
    idx, w = atlas.weights(lat, lon)
    assert atlas.observer_water_depth(idx, np.where(w > 1e-6, 0.5, 0.0), x, y)[0] == pytest.approx(h_mid, rel=0.02)
    kc, tlc = values_at(atlas, lat_deg=atlas.lat_deg[[1, 4]], lon_deg=atlas.lon_deg[[1, 4]], **kw)
    kt, tlt = values_at(atlas, lat_deg=lat, lon_deg=lon, **kw)
    h = atlas.slab(1, 1)[2][:, 0].mean(), atlas.slab(1, 4)[2][:, 0].mean()  # on a ring 200 m out
    share = (kt[0] - kc[1]) / (kc[0] - kc[1])  # position 1's weight (0.5 with the bilinear weights)
    assert (share > 0.5) == (abs(math.log(h[0] / h_mid)) < abs(math.log(h[1] / h_mid)))
    assert 0.0 < share < 1.0 and abs(share - 0.5) > 0.01  # 0.52 here: 925 and 192 m about 468 m
    assert tlt[0] == pytest.approx(share * tlc[0] + (1.0 - share) * tlc[1], abs=1e-6)
    with pytest.raises(InputError, match=r"observer 0: .* outside the atlas's lattice"):
        values_at(atlas, lat_deg=[42.5], lon_deg=[5.0], **kw)
    # between the middle row and the left-out northern row: no tables to weight
    with pytest.raises(InputError, match=r"not surrounded by the atlas's tables"):
        values_at(atlas, lat_deg=[atlas.lat_deg[3] + 0.03], lon_deg=[atlas.lon_deg[3] + 0.01], **kw)
    with pytest.raises(InputError, match=r"month 5 is not in the atlas"):
        values_at(atlas, lat_deg=atlas.lat_deg[:1], lon_deg=atlas.lon_deg[:1], **{**kw, "month": 5})


def test_a_rebuild_recomputes_only_missing_damaged_or_changed_tables(built, tmp_path):
    area, out, _ = built
    copy = tmp_path / "a.zarr"
    shutil.copytree(out, copy)
    before = _tables(copy)
    assert build_atlas_file(area, copy, workers=2)["tables_built"] == 0
    # a chunk deleted (table month 2, origin 2), a chunk with a flipped byte (month 8, origin 3),
    # and a table whose inputs changed (its stored hash no longer the plan's: month 8, origin 5)
    import zarr

    (copy / "tl_db" / "c" / "0" / "2" / "0" / "0" / "0" / "0" / "0").unlink()
    chunk = copy / "k_db" / "c" / "1" / "3" / "0" / "0" / "0" / "0"
    data = bytearray(chunk.read_bytes())
    data[len(data) // 2] ^= 0xFF
    chunk.write_bytes(bytes(data))
    zarr.open_group(str(copy), mode="r+")["table_hash"][1, 5] = 12345
    atlas = open_store(copy)
    assert not atlas.done[0, 2]  # found missing at open
    with pytest.raises(AtlasFileError, match=r"a damaged chunk"):  # never read as numbers
        atlas.slab(1, 3)
    with pytest.raises(AtlasFileError, match=r"not built or is damaged; tmakit atlas build"):
        atlas.sel(month=2, origin=2)
    info = build_atlas_file(area, copy, workers=2)
    assert info["tables_built"] == 3 and info["runs"] == 12 * 2
    assert _same(_tables(copy), before)


def test_stores_that_are_not_this_atlas_are_refused_naming_what_differs(built, tmp_path):
    area, out, _ = built
    notes = tmp_path / "notes.zarr"
    notes.mkdir()
    (notes / "keep.txt").write_text("mine")
    with pytest.raises(AtlasFileError, match=r"exists and is not a tmakit atlas; not replaced"):
        build_atlas_file(area, notes)
    assert (notes / "keep.txt").read_text() == "mine"
    other = tmp_path / "other.zarr"
    shutil.copytree(out, other)
    wider = load_atlas_area(tmp_path / "wider", spacing_km=7.0)
    with pytest.raises(AtlasFileError, match=r"other axes or another area: its origin_lat_deg"):
        build_atlas_file(wider, other)
    meta = json.loads((other / "zarr.json").read_text())
    meta["attributes"]["tmakit_format"] = 99
    (other / "zarr.json").write_text(json.dumps(meta))
    with pytest.raises(AtlasFileError, match=r"an atlas of tmakit format 99 \(written by a newer tmakit\); "
                                             r"this version reads format 1"):
        open_store(other)
    with pytest.raises(AtlasFileError, match=r"format 99"):
        build_atlas_file(area, other)


@pytest.mark.slow
def test_a_dask_cluster_losing_a_worker_mid_build_ends_with_identical_tables(built, tmp_path):
    from distributed import Client, LocalCluster

    area, out, _ = built
    store = tmp_path / "dask.zarr"
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address="127.0.0.1:0") as cluster, Client(cluster) as client:
        pids = list(client.run(os.getpid).values())
        result = {}

        def build():
            result["info"] = build_atlas_file(area, store, scheduler=cluster.scheduler_address)

        thread = threading.Thread(target=build)
        thread.start()
        deadline = time.monotonic() + 120
        killed = False
        while thread.is_alive() and time.monotonic() < deadline:
            done_dir = store / "done" / "c"
            if not killed and done_dir.exists() and sum(1 for _ in done_dir.rglob("*") if _.is_file()) >= 2:
                os.kill(pids[0], signal.SIGKILL)  # a worker dies with a table under way
                killed = True
            time.sleep(0.05)
        thread.join(timeout=120)
    assert killed and "info" in result
    assert result["info"]["tables_built"] == 12
    assert open_store(store).done.all()
    assert _same(_tables(store), _tables(out))
