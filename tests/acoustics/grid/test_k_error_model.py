"""K's error model in a grid (format 3, `acoustics.grid.kerror`), read through the face; a
format-2 grid's one sd by range read as what it meant; and the model a study's members measure
(`acoustics.sensitivity.errormodel`)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import xarray as xr
from numpy.testing import assert_allclose

import acoustics
from acoustics.errors import GridFileError
from acoustics.grid.dataset import with_k_error_model, with_k_error_sd
from acoustics.grid.kerror import (
    MODEL_VARS,
    TABLE_BAND_OWN_GROWTH_DB_PER_KM,
    TABLE_BAND_OWN_SD_DB,
    TABLE_RESIDUAL_LENGTH_M,
    TABLE_RESIDUAL_SD_DB,
    KErrorModel,
)
from acoustics.sensitivity.errormodel import measure


def _model(tables, offset, residual, length, corr):
    c, m = len(tables.classes), len(tables.bands)
    coords = {"class": tables.dataset["class"].values, "band": tables.dataset["band"].values}
    return xr.Dataset({"k_offset_sd_db": (("class", "band"), np.broadcast_to(offset, (c, m)).copy()),
                       "k_residual_sd_db": (("class", "band"), np.broadcast_to(residual, (c, m)).copy()),
                       "k_residual_length_m": (("class",), np.full(c, length)),
                       "k_offset_band_correlation": (("class",), np.full(c, corr))}, coords=coords)


def test_a_grids_model_is_what_the_face_answers(tiny_grid, tmp_path):
    tables = acoustics.open_tables(tiny_grid)
    ds = with_k_error_model(tables.dataset, _model(tables, [3.0, 4.0], [1.0, 2.0], 850.0, 0.6), "test")
    path = tmp_path / "model.nc"
    acoustics.write_grid(ds, path)
    model = acoustics.open_tables(path).k_error_model(0)
    assert model.offset_sd_db == (3.0, 4.0) and model.offset_band_correlation == 0.6
    assert model.residual_length_m == 850.0
    # the members' K is computed as the tables' is: the tables' own residual stands beside theirs
    assert_allclose(model.residual_sd_db, [math.hypot(1.0, TABLE_RESIDUAL_SD_DB), math.hypot(2.0, TABLE_RESIDUAL_SD_DB)])
    assert model.offset_growth_db_per_km == 0.0  # a flat grid holds everywhere


def test_without_a_model_the_classs_number_is_the_offset(tiny_grid):
    tables = acoustics.open_tables(tiny_grid)
    model = tables.k_error_model(1)
    assert model.offset_sd_db == (tables.classes[1].k_error_sd_db,) * len(tables.bands)
    assert model.residual_sd_db == (TABLE_RESIDUAL_SD_DB,) * len(tables.bands)
    assert model.residual_length_m == TABLE_RESIDUAL_LENGTH_M


def test_a_format_2_map_opens_and_is_read_as_the_offset(tiny_grid):
    # the previous release's `tmakit sensitivity --into`: the rms of K's error by range
    tables = acoustics.open_tables(tiny_grid)
    sd = np.broadcast_to(np.linspace(1.0, 5.0, tables.range_m.size), tables.k_grid_db.shape).copy()
    old = with_k_error_sd(tables.dataset, sd, "test").assign_attrs(tmakit_format=2)
    model = acoustics.open_tables(old).k_error_model(0)
    assert_allclose(model.offset_sd_db, [np.median(sd[0, 0])] * len(tables.bands))


def test_a_radial_grids_model_is_read_at_the_bearing(tiny_radial_tables):
    t = tiny_radial_tables
    c, m, n = len(t.classes), len(t.bands), t.bearing_axis_deg.size
    off = np.broadcast_to(np.arange(n, dtype=float) + 1.0, (c, m, n)).copy()     # 1, 2, 3 dB on 0, 120, 240
    coords = {"class": t.dataset["class"].values, "band": t.dataset["band"].values, "bearing": t.bearing_axis_deg}
    model = xr.Dataset({"k_offset_sd_db": (("class", "band", "bearing"), off),
                        "k_residual_sd_db": (("class", "band", "bearing"), np.zeros((c, m, n))),
                        "k_residual_length_m": (("class",), np.full(c, 500.0)),
                        "k_offset_band_correlation": (("class",), np.ones(c))}, coords=coords)
    tables = acoustics.open_tables(with_k_error_model(t.dataset, model, "test"))
    assert_allclose(tables.k_error_model(0, bearing_deg=60.0).offset_sd_db, [1.5] * m)
    assert_allclose(tables.k_error_model(0, bearing_deg=300.0).offset_sd_db, [2.0] * m)    # across 360
    assert_allclose(tables.k_error_model(0).offset_sd_db, [2.0] * m)                        # the median
    assert tables.k_error_model(0).offset_growth_db_per_km > 0.0    # tables of one position


@pytest.mark.parametrize("change, message", [
    (lambda ds: ds.drop_vars("k_residual_length_m"), "missing k_residual_length_m"),
    (lambda ds: ds.assign(k_offset_band_correlation=ds["k_offset_band_correlation"] * 0 + 1.5), r"outside \[0, 1\]"),
    (lambda ds: ds.assign(k_residual_sd_db=ds["k_residual_sd_db"] * 0 - 1.0), r"outside \[0, inf\]"),
])
def test_a_broken_model_is_refused(tiny_grid, change, message):
    tables = acoustics.open_tables(tiny_grid)
    ds = change(with_k_error_model(tables.dataset, _model(tables, 2.0, 1.0, 500.0, 1.0), "test"))
    with pytest.raises(GridFileError, match=message):
        acoustics.open_tables(ds)


def test_the_members_model_is_measured():
    # members whose K error is an offset per member (rms 3 dB, the bands' offsets correlated by
    # 0.5 about zero) and a residual along range with a known correlation length
    rng = np.random.default_rng(2)
    e, m, r_n, step, length = 400, 2, 400, 100.0, 800.0
    r = np.arange(1, r_n + 1) * step
    common = rng.normal(0.0, 3.0 * math.sqrt(0.5), (e, 1))
    offsets = common + rng.normal(0.0, 3.0 * math.sqrt(0.5), (e, m))
    rho = math.exp(-step / length)
    res = np.empty((e, m, r_n))
    res[..., 0] = rng.normal(0.0, 2.0, (e, m))
    for k in range(1, r_n):
        res[..., k] = rho * res[..., k - 1] + math.sqrt(1 - rho * rho) * rng.normal(0.0, 2.0, (e, m))
    dk = (offsets[..., None] + res)[:, None]                                       # (E, C=1, M, R)
    offset_sd, residual_sd, lengths, corr = measure(dk, r)
    # tolerances: 400 members' sampling (offset rms +- 4 %); the residual's range-mean leaks into the
    # measured offset (its sd over 40 km of range with 800 m correlation: ~0.4 dB); the length's
    # estimate from the pooled autocorrelation of 800 series of 400 steps
    assert_allclose(offset_sd[0], 3.0, rtol=0.1)
    assert_allclose(residual_sd[0], 2.0, rtol=0.05)
    assert_allclose(lengths[0], length, rtol=0.1)
    assert abs(corr[0] - 0.5) < 0.1
    assert set(MODEL_VARS) == {"k_offset_sd_db", "k_residual_sd_db", "k_residual_length_m", "k_offset_band_correlation"}


def test_tables_read_everywhere_do_not_grow_their_error(tiny_radial_tables):
    # a study's member is a sea computed where the observer starts and read from the observer
    # wherever it goes: the trackers read the nominal tables alike, with no distance to grow by
    anywhere = tiny_radial_tables.as_everywhere()
    assert anywhere.distance_from_origin_m([3000.0], [4000.0]) is None
    assert anywhere.k_error_model(0).offset_growth_db_per_km == 0.0
    assert tiny_radial_tables.distance_from_origin_m([3000.0], [4000.0])[0] == 5000.0
    np.testing.assert_array_equal(anywhere.k_grid_db, tiny_radial_tables.k_grid_db)


def test_part_of_the_tables_residual_is_each_bands_own(tiny_radial_tables):
    # the tables' interference patterns are off each its own way (bench.kerror_check): the trackers
    # take that part as each band's own, the rest of the residual as common, the total unchanged
    from tracker.levels import LevelErrors

    model = tiny_radial_tables.k_error_model(0)
    assert model.band_own_sd_db == TABLE_BAND_OWN_SD_DB and model.band_own_growth_db_per_km == TABLE_BAND_OWN_GROWTH_DB_PER_KM
    n = len(tiny_radial_tables.bands)
    errors = LevelErrors.of_tables(tiny_radial_tables, 0)
    own = [c for c in errors.components if c.band >= 0 and c.length_m is not None]
    common = [c for c in errors.components if c.band < 0 and c.length_m is not None]
    assert [c.band for c in own] == list(range(n)) and len(common) == 1
    assert_allclose([c.sd_db for c in own], TABLE_BAND_OWN_SD_DB)
    assert_allclose(math.hypot(common[0].sd_db, own[0].sd_db), TABLE_RESIDUAL_SD_DB)
    assert_allclose(math.hypot(common[0].growth_db_per_km, own[0].growth_db_per_km), model.residual_growth_db_per_km)
    # one band: its own part and the common one are one residual, as before
    one = [c for c in LevelErrors.of_tables(tiny_radial_tables, 0, [0]).components if c.length_m is not None]
    assert len(one) == 1 and one[0].band < 0
    assert_allclose(one[0].sd_db, TABLE_RESIDUAL_SD_DB)
    # a flat grid's tables hold everywhere: nothing grows
    assert tiny_radial_tables.as_everywhere().k_error_model(0).band_own_growth_db_per_km == 0.0


def test_a_bands_own_part_larger_than_the_residual_is_refused():
    with pytest.raises(ValueError, match="band_own_sd_db"):
        KErrorModel(offset_sd_db=(3.0, 3.0), residual_sd_db=(1.0, 2.0), band_own_sd_db=1.5)
    with pytest.raises(ValueError, match="band_own_growth_db_per_km"):
        KErrorModel(offset_sd_db=(3.0,), residual_sd_db=(2.0,), residual_growth_db_per_km=0.5,
                    band_own_growth_db_per_km=0.6)


def test_the_check_measures_each_bands_own_part():
    # lines of a common residual (sd 2 dB, 800 m correlation) and each band's own (sd 0.7 dB,
    # independent by band): the check's estimate finds the own part, not the common one
    from bench.kerror_check import band_own_sd_db

    rng = np.random.default_rng(3)
    r, m = 4000, 3
    common = np.zeros(r)
    rho = math.exp(-250.0 / 800.0)
    for k in range(1, r):
        common[k] = rho * common[k - 1] + math.sqrt(1 - rho * rho) * rng.normal(0.0, 2.0)
    resid = common[:, None] + rng.normal(0.0, 0.7, (r, m))
    # tolerance: 4000 x 3 draws of the own part (its sd's relative error about 1 %)
    assert abs(band_own_sd_db(resid) - 0.7) < 0.03
    assert band_own_sd_db(resid[:, :1]) == 0.0  # one band has no own part to tell
