"""P_D maps on real BELLHOP tables (acoustics.grid.pdmap, detectionsigma): the detection map's step
as sigma goes to 0, P_D = 1/2 at its edge, sigma where it comes from, and detection that passes
the table's last range said as such, never given as a range."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from numpy.testing import assert_allclose

import acoustics
from acoustics.detection import band_snr_db, indicator_snr
from acoustics.grid.detectionmap import class_k_db, detection_map
from acoustics.grid.detectionsigma import SigmaOverride, detection_sigma_db
from acoustics.grid.pdmap import pd_map, table_reach
from acoustics.pd import normal_cdf
from envdata.errors import InputError

pytestmark = pytest.mark.bellhop


@pytest.fixture(scope="module")
def flat(tiny_grid):
    return acoustics.open_tables(tiny_grid)


def _step(tables, cls_name, bearings):
    """Where each band is detected, written out from eqs. 2 and 11 (the detection map's rule)."""
    ic = tables.class_index(cls_name)
    cls = tables.classes[ic]
    sonar = tables.area.sonar
    k = class_k_db(tables, cls_name, np.asarray(bearings, dtype=float))
    snr = band_snr_db(k, cls.noise_mean_db, tables.noise_band_db[:, None], sonar.directivity_index_db)
    q = indicator_snr(snr, tables.bandwidth_hz[:, None], sonar.integration_time_s)
    return np.nan_to_num(q, nan=0.0) >= sonar.detection_threshold


@pytest.mark.parametrize("cls_name", ["SUB", "SHIP"])
def test_as_sigma_goes_to_zero_p_d_is_the_detection_map_s_step_at_every_range(tiny_radial_tables, cls_name):
    t = tiny_radial_tables
    bearings = [0.0, 60.0, 120.0, 300.0]
    step = _step(t, cls_name, bearings)
    pm = pd_map(t, cls_name, bearings, override=SigmaOverride(sigma_db=1e-9))
    # no range of the table sits within 1e-6 dB of the edge, so 1e-9 dB of sigma is a step there
    assert np.nanmin(np.abs(pm.excess_db)) > 1e-6
    assert np.array_equal(pm.pd[:, :-1, :], step.astype(float))
    # a class without scatter of its own (source level and K offset sd 0) still has the tables' own
    # residual (acoustics.grid.kerror): its sigma is that and nothing else
    from acoustics.grid.kerror import TABLE_RESIDUAL_SD_DB

    ic = t.class_index(cls_name)
    exact = dataclasses.replace(t.classes[ic], noise_sd_db=0.0, k_error_sd_db=0.0)
    quiet = dataclasses.replace(t, classes=tuple(exact if i == ic else c for i, c in enumerate(t.classes)))
    assert_allclose(pd_map(quiet, cls_name, bearings).sigma.total_db, TABLE_RESIDUAL_SD_DB)


def test_p_d_is_one_half_where_the_detection_map_puts_its_edge(tiny_radial_tables):
    t = tiny_radial_tables
    bearings = t.bearing_axis_deg
    pm = pd_map(t, "SUB", bearings)
    dm = detection_map(t, "SUB", bearings)
    # the 0.5 range of every band is the detection map's range to the metre
    assert_allclose(pm.ranges_m[0.5][:-1], dm.band_range_m, rtol=0, atol=0.0, equal_nan=True)
    for ib in range(len(t.bands)):
        for j in range(bearings.size):
            edge = np.flatnonzero(t.range_m == dm.band_range_m[ib, j])[0]
            # P_D >= 1/2 on the edge's range, < 1/2 on the next: the crossing SE = 0 lies between,
            # and there, at K = K_needed, P_D is Phi(0) = 1/2 exactly
            assert pm.pd[j, ib, edge] >= 0.5 > pm.pd[j, ib, edge + 1]
            se0, se1 = pm.excess_db[j, ib, edge], pm.excess_db[j, ib, edge + 1]
            sigma = pm.sigma.total_db[j, ib, edge]
            assert_allclose(pm.pd[j, ib, edge], normal_cdf(se0 / sigma), rtol=1e-12)
            assert se0 >= 0.0 > se1
    assert pd_map(t, "SUB", [0.0]).pd.shape == (1, len(t.bands) + 1, t.range_m.size)


def test_sigma_is_the_source_level_and_k_error_sds_or_the_grid_s_map(flat, tiny_grid):
    from acoustics.grid.kerror import TABLE_RESIDUAL_SD_DB

    sub = flat.classes[flat.class_index("SUB")]
    sigma = detection_sigma_db(flat, flat.class_index("SUB"), np.array([500.0, 4000.0]))
    # 2.5 dB source level, 2.0 dB K offset, the tables' own 1.94 dB residual: 3.74 dB
    assert_allclose(sigma.total_db, np.sqrt(sub.noise_sd_db ** 2 + sub.k_error_sd_db ** 2 + TABLE_RESIDUAL_SD_DB ** 2))
    assert np.all(sigma.per_look_db == 0.0) and np.array_equal(sigma.persistent_db, sigma.total_db)
    # a sensitivity study's map in the grid replaces the class's one number where it has values
    from acoustics.grid.dataset import with_k_error_sd

    sd = np.full(flat.k_grid_db.shape, 6.0)
    mapped = acoustics.open_tables(with_k_error_sd(tiny_grid, sd, "test map"))
    got = detection_sigma_db(mapped, 0, np.array([1000.0])).total_db
    assert_allclose(got, np.sqrt(sub.noise_sd_db ** 2 + 6.0 ** 2 + TABLE_RESIDUAL_SD_DB ** 2))
    # the user's sigma replaces the persistent part; a per-look part adds to one look's sigma
    mine = detection_sigma_db(flat, 0, np.array([1000.0]), override=SigmaOverride(sigma_db=4.0, look_sd_db=3.0))
    assert_allclose(mine.total_db, 5.0)
    assert "sigma 4 dB given" in mine.source and "per-look sd 3 dB given" in mine.source
    for bad in (0.0, -1.0, float("nan"), float("inf")):
        with pytest.raises(InputError, match="--sigma-db: must be > 0 dB"):
            SigmaOverride(sigma_db=bad)
    with pytest.raises(InputError, match="--look-sd-db: must be >= 0 dB"):
        SigmaOverride(look_sd_db=-0.5)


def test_detection_past_the_table_s_edge_is_said_never_given_as_a_range(tiny_radial_tables, flat):
    for tables in (tiny_radial_tables, flat):
        bearings = tables.bearing_axis_deg if tables.bearing_axis_deg is not None else [0.0]
        ship = pd_map(tables, "SHIP", bearings)
        # the ship at 133 dB is loud at the tables' last range (5 km): beyond the table, no range
        assert np.all(ship.edge_pd[:-1] >= 0.1)
        for level in (0.9, 0.5, 0.1):
            assert np.all(ship.beyond[level]) and np.all(np.isnan(ship.ranges_m[level]))
        sub = pd_map(tables, "SUB", bearings)
        assert not np.any(sub.beyond[0.1]) and np.all(np.isfinite(sub.ranges_m[0.1]))
        assert np.all(sub.ranges_m[0.9] <= sub.ranges_m[0.5]) and np.all(sub.ranges_m[0.5] <= sub.ranges_m[0.1])
        reach = {(r.cls_name, r.band): r for r in table_reach(tables)}
        assert all(reach[("SUB", b)].inside and reach[("SUB", b)].needed_m is None for b in tables.band_names)
        for band in tables.band_names:
            r = reach[("SHIP", band)]
            assert not r.inside and r.bearings_beyond == len(bearings) and r.needed_m > tables.range_m[-1]
            assert 10.0 <= r.spreading_db_per_decade <= 20.0
