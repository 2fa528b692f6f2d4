"""Band averaging of TL: intensity, not dB; spectrum weights; quadrature."""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from numpy.testing import assert_allclose

import envdata
from acoustics.kcurve import band_average_tl_db, band_frequencies_hz, band_weights

CLS = envdata.TargetClass(name="c", depth_m=10.0, speed_mean_mps=5.0, speed_sd_mps=1.0, noise_mean_db=100.0)


def test_band_average_is_over_intensity():
    tl = band_average_tl_db(np.array([[60.0], [70.0]]), np.array([0.5, 0.5]), 200.0)
    assert_allclose(tl, -10 * np.log10((1e-6 + 1e-7) / 2), rtol=0, atol=1e-9)  # 62.60 dB, not 65


def test_shadow_capped_at_tl_max():
    tl = band_average_tl_db(np.array([[400.0], [500.0]]), np.array([0.5, 0.5]), 150.0)
    assert tl[0] == 150.0


@given(st.floats(50.0, 5000.0), st.floats(1.01, 10.0), st.integers(2, 21))
def test_weights_sum_to_one_and_integrate_the_spectrum(low, ratio, n):
    band = envdata.Band(name="b", low_hz=low, high_hz=low * ratio)
    f = band_frequencies_hz(band, n)
    w = band_weights(CLS, f)
    assert_allclose(w.sum(), 1.0, rtol=1e-12)
    assert f[0] == low and np.isclose(f[-1], low * ratio)
    # f^-2 puts more weight at the low end of the band
    assert w[0] / (f[1] - f[0]) >= w[-1] / (f[-1] - f[-2]) * 0.999


def test_quadrature_converges_to_the_analytic_band_mean():
    # intensity ~ f^-1 under an f^-2 spectrum over 100-300 Hz: mean = int f^-3 / int f^-2
    band = envdata.Band(name="b", low_hz=100.0, high_hz=300.0)
    f = band_frequencies_hz(band, 41)
    mean = np.dot(band_weights(CLS, f), 1.0 / f)
    exact = ((100.0 ** -2 - 300.0 ** -2) / 2) / (100.0 ** -1 - 300.0 ** -1)
    assert_allclose(mean, exact, rtol=1e-3)
