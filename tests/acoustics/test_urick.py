"""Urick approximate formula (Grinenkov & Mashoshin eq. 13), Thorp absorption, spectral terms."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from numpy.testing import assert_allclose

import envdata
from acoustics import k_urick_db, spectral_term_db, spherical_tl_db, thorp_db_per_km

P0_CLASS = envdata.TargetClass(name="c", depth_m=10.0, speed_mean_mps=5.0, speed_sd_mps=1.0, noise_mean_db=100.0)
FB1 = envdata.Band(name="FB1", low_hz=100.0, high_hz=300.0)


def test_spherical_spreading_gives_60_db_at_1_km():
    assert_allclose(spherical_tl_db(1000.0), 60.0, rtol=0, atol=0.01)


def test_thorp_by_hand_at_1_khz():
    # 3.3e-3 + 0.11 * 1/2 + 44 * 1/4101 + 3e-4 = 0.069329 dB/km (JKPS eq. 1.34, as BELLHOP applies it)
    assert_allclose(thorp_db_per_km(1000.0), 0.0033 + 0.055 + 44.0 / 4101.0 + 0.0003, rtol=0, atol=1e-9)


def test_eq13_by_hand_fb1_at_10_km():
    # f_ekv = sqrt(100 * 300) = 173.205 Hz; -20 lg 0.173205 = 15.2288; 10 lg 200 = 23.0103
    # beta(173.2 Hz) = 3.3e-3 + 0.11*0.03/1.03 + 44*0.03/4100.03 + 3e-4*0.03 = 0.0068348 dB/km
    # K = 15.2288 + 23.0103 - 0.068348 - 20 lg 10 - 60 = -41.8292 dB
    beta = float(thorp_db_per_km(FB1.center_hz))
    assert_allclose(beta, 0.0068348, rtol=0, atol=1e-7)
    assert_allclose(k_urick_db(10_000.0, FB1, P0_CLASS, beta_db_per_km=beta), -41.8292, rtol=0, atol=1e-3)


def test_spectral_term_is_eq13_first_two_terms_for_f_minus_2():
    for lo, hi in [(100.0, 300.0), (300.0, 1000.0), (1000.0, 3000.0), (20.0, 21.0)]:
        band = envdata.Band(name="b", low_hz=lo, high_hz=hi)
        expected = -20 * math.log10(band.center_hz / 1000.0) + 10 * math.log10(hi - lo)
        assert_allclose(spectral_term_db(P0_CLASS, band), expected, rtol=0, atol=1e-9)


def test_single_frequency_band_has_no_bandwidth_term():
    band = envdata.Band(name="F500", low_hz=500.0, high_hz=500.0)
    assert_allclose(spectral_term_db(P0_CLASS, band), -20 * math.log10(0.5), rtol=0, atol=1e-12)
    ross = envdata.TargetClass(name="r", depth_m=5.0, speed_mean_mps=2.0, speed_sd_mps=1.0,
                               source_level_model=envdata.SourceLevelModel.ROSS)
    assert spectral_term_db(ross, band) == 0.0  # Ross level is given at the band centre itself


@given(st.floats(100.0, 200_000.0), st.floats(1.0, 10_000.0))
def test_urick_with_zero_anomaly_falls_with_range(r1, dr):
    beta = float(thorp_db_per_km(FB1.center_hz))
    k1, k2 = k_urick_db(np.array([r1, r1 + dr]), FB1, P0_CLASS, beta_db_per_km=beta)
    assert k2 < k1


@given(st.floats(-200.0, 200.0))
def test_db_ratio_round_trip(level_db):
    assert_allclose(10 * np.log10(10 ** (level_db / 10)), level_db, rtol=0, atol=1e-9)
