"""The depth likelihood read from the tables along a track (`tracker.depth.likelihood`)."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose

from tracker.depth.likelihood import RANGE_SCALE_SD, TrackDepthLikelihood

pytestmark = pytest.mark.bellhop
SPAN_M = (2.0, 300.0)


@pytest.fixture(scope="module")
def setting(tiny_depth_grid_file):
    """The tiny grid's SUB tables, a 30 min track receding from 3 to 6 km on bearing 40 deg, and
    its levels from the tables' K at 60 m (every band, high SNR, a little noise)."""
    from acoustics.grid.opentables import open_tables

    tables = open_tables(tiny_depth_grid_file)
    ic = tables.class_index("SUB")
    t = 20.0 * np.arange(90)
    r = np.linspace(3000.0, 6000.0, t.size)
    b = np.full(t.size, 40.0)
    plain = TrackDepthLikelihood(tables, ic, tables.band_names, SPAN_M, range_scale_sd=0.0)
    k = np.stack([m.at(np.asarray(60.0), r, b) for m in plain._mean], axis=-1)
    rng = np.random.default_rng(3)
    level = plain._base_db + k + rng.normal(0.0, 0.3, k.shape)
    snr = np.full(k.shape, 30.0)
    z = np.array([10.0, 30.0, 60.0, 120.0, 250.0])
    return tables, ic, t, r, b, level, snr, z


def test_a_negative_or_missing_range_scale_sd_is_refused(setting):
    tables, ic = setting[:2]
    for bad in (-0.1, float("nan")):
        with pytest.raises(ValueError, match="range_scale_sd"):
            TrackDepthLikelihood(tables, ic, tables.band_names, SPAN_M, range_scale_sd=bad)


def test_the_range_scale_integral_holds_each_scale_it_weighs(setting):
    # L(z) over the scales is a weighted sum of the likelihood along the track times each scale:
    # never below any one weighted term, and with no spread the track as it is
    tables, ic, t, r, b, level, snr, z = setting
    plain = TrackDepthLikelihood(tables, ic, tables.band_names, SPAN_M, range_scale_sd=0.0)
    wide = TrackDepthLikelihood(tables, ic, tables.band_names, SPAN_M)
    assert wide.scales.size > 1 and np.isclose(np.exp(wide.log_scale_weight).sum(), 1.0)
    # the nodes' weights give ln s its sd and kurtosis (a normal's 3)
    w, u = np.exp(wide.log_scale_weight), np.log(wide.scales)
    assert_allclose([np.sum(w * u), np.sum(w * u ** 2), np.sum(w * u ** 4)],
                    [0.0, RANGE_SCALE_SD ** 2, 3.0 * RANGE_SCALE_SD ** 4], atol=1e-12)
    ll = wide(z, t, r, b, level, snr)[:, -1]
    for s, lw in zip(wide.scales, wide.log_scale_weight):
        assert np.all(ll >= lw + plain(z, t, s * r, b, level, snr)[:, -1] - 1e-9)
    assert_allclose(plain(z, t, r, b, level, snr), TrackDepthLikelihood(
        tables, ic, tables.band_names, SPAN_M, range_scale_sd=0.0)(z, t, r, b, level, snr))


def test_a_track_off_in_range_costs_the_true_depth_less(setting):
    # a tracker's track 25 % long: read along it without the scale's spread the true depth (60 m)
    # falls behind the best by more than with it
    tables, ic, t, r, b, level, snr, z = setting
    plain = TrackDepthLikelihood(tables, ic, tables.band_names, SPAN_M, range_scale_sd=0.0)
    wide = TrackDepthLikelihood(tables, ic, tables.band_names, SPAN_M)
    j = int(np.flatnonzero(z == 60.0)[0])

    def behind(like):
        ll = like(z, t, 1.25 * r, b, level, snr)[:, -1]
        return ll.max() - ll[j]

    assert behind(wide) < behind(plain)
    # along the true track the true depth leads either way
    for like in (plain, wide):
        ll = like(z, t, r, b, level, snr)[:, -1]
        assert np.argmax(ll) == j


def _below_the_bottom(like, depth_from_m: float, range_from_m: float):
    """The likelihood's tables with no water at ``depth_from_m`` and deeper beyond
    ``range_from_m`` (a bottom that rises along the radial)."""
    import dataclasses

    out = []
    for m in like._mean:
        k = m.k_db.copy()
        k[np.ix_(range(k.shape[0]), np.flatnonzero(m.depth_m >= depth_from_m),
                 np.flatnonzero(m.range_m >= range_from_m))] = np.nan
        out.append(dataclasses.replace(m, k_db=k))
    like._mean = out
    return like


def test_a_depth_below_the_bottom_along_the_track_is_ruled_out(setting):
    # the track recedes from 3 to 6 km; beyond 4.5 km there is no water at 250 m: a target at
    # 250 m cannot be on that track (its likelihood would otherwise lack those cycles' terms and
    # win); up to 4.5 km it is judged as any other depth
    tables, ic, t, r, b, level, snr, z = setting
    like = _below_the_bottom(TrackDepthLikelihood(tables, ic, tables.band_names, SPAN_M, range_scale_sd=0.0),
                             200.0, 4500.0)
    ll = like(z, t, r, b, level, snr)
    deep = z >= 200.0
    wet = like._mean[0].range_m
    first_dry = int(np.flatnonzero(r > wet[wet < 4500.0].max())[0])   # K linear between range nodes
    assert np.all(np.isneginf(ll[deep, first_dry:])) and np.all(np.isfinite(ll[deep, :first_dry]))
    assert np.all(np.isfinite(ll[~deep]))
    from tracker.depth.posterior import posterior

    post = posterior(z, ll[:, -1], SPAN_M)
    assert np.all(post.weight[deep] == 0.0) and np.isclose(post.weight.sum(), 1.0)


def test_cycles_before_the_track_begins_say_nothing(setting):
    # a track known from cycle 30 on (NaN ranges before, as a tack's line back gives): no depth is
    # judged on the cycles before, none is ruled out
    tables, ic, t, r, b, level, snr, z = setting
    like = TrackDepthLikelihood(tables, ic, tables.band_names, SPAN_M, range_scale_sd=0.0)
    late = r.copy()
    late[:30] = np.nan
    ll = like(z, t, late, b, level, snr)
    assert np.all(ll[:, :30] == 0.0) and np.all(np.isfinite(ll[:, 30:])) and np.all(ll[:, -1] < 0.0)
