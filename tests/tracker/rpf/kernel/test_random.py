"""The kernel's random numbers: per-run xoshiro256+ generators and the ziggurat normal and
exponential samplers, by their tables, their distributions and the fused fills' streams."""

from __future__ import annotations

import math

import numpy as np
from numpy.testing import assert_allclose
from scipy import stats

from tests.tracker.rpf.kernel.wrappers import exponentials, exponentials_filled, normal_pairs_filled, normals, uniforms
from tracker.rpf.kernel.random import (
    ZIGGURAT_EXP_F,
    ZIGGURAT_EXP_R,
    ZIGGURAT_EXP_X,
    ZIGGURAT_F,
    ZIGGURAT_R,
    ZIGGURAT_X,
    seed_states,
)


def test_generator_is_seeded_per_run_and_reproducible():
    a = seed_states(np.random.default_rng(3), 5)
    b = seed_states(np.random.default_rng(3), 5)
    assert a.dtype == np.uint64 and a.shape == (5, 4)
    assert_allclose(a.astype(float), b.astype(float), rtol=0, atol=0)
    u = uniforms(a[0].copy(), 200_000)
    assert 0.0 <= u.min() and u.max() < 1.0
    assert stats.kstest(u, "uniform").pvalue > 1e-3
    assert not np.array_equal(uniforms(a[0].copy(), 10), uniforms(a[1].copy(), 10))


def test_ziggurat_layers_have_equal_areas():
    # Marsaglia & Tsang's 256-layer table: each layer x_i (f(x_(i+1)) - f(x_i)) is v
    x, f = ZIGGURAT_X, ZIGGURAT_F
    areas = x[1:-1] * (f[2:] - f[1:-1])
    assert_allclose(areas, 0.00492867323399, rtol=1e-8)  # v to its 12 printed digits


def test_ziggurat_normals_are_standard_normal():
    g = normals(seed_states(np.random.default_rng(1), 1)[0], 500_000)
    assert stats.kstest(g, "norm").pvalue > 1e-3
    assert_allclose([g.mean(), g.var()], [0.0, 1.0], atol=0.006)  # 4.5 standard errors
    # the tail beyond r = 3.654 comes from the separate tail sampler: 2 (1 - Phi(r)) = 2.58e-4,
    # so ~258 of 1e6 draws (Poisson sd 16)
    tail = np.sum(np.abs(g) > ZIGGURAT_R)
    assert abs(tail - 1e6 * 2 * stats.norm.sf(ZIGGURAT_R)) < 5 * 16
    assert stats.kstest(np.abs(g[np.abs(g) > 2.5]) - 2.5,
                        lambda x: 1 - stats.norm.sf(x + 2.5) / stats.norm.sf(2.5)).pvalue > 1e-3


def test_fused_noise_fill_is_the_same_stream_as_normal():
    s = seed_states(np.random.default_rng(7), 1)[0]
    gx, gy = normal_pairs_filled(s.copy(), 100_000)
    g = normals(s.copy(), 100_000)
    # the same draws; a tail value may differ by an ulp (FMA contraction differs by inlining)
    assert_allclose(gx, g[0::2], rtol=1e-15, atol=0)
    assert_allclose(gy, g[1::2], rtol=1e-15, atol=0)
    e = exponentials_filled(s.copy(), 100_000)
    assert_allclose(e, exponentials(s.copy(), 100_000), rtol=1e-15, atol=0)


def test_ziggurat_exponentials_are_standard_exponential():
    x, f = ZIGGURAT_EXP_X, ZIGGURAT_EXP_F
    assert_allclose(x[1:-1] * (f[2:] - f[1:-1]), 0.0039496598225815571993, rtol=1e-8)
    e = exponentials(seed_states(np.random.default_rng(6), 1)[0], 500_000)
    assert e.min() >= 0.0
    assert stats.kstest(e, "expon").pvalue > 1e-3
    assert_allclose([e.mean(), e.var()], [1.0, 1.0], atol=0.012)  # ~4 standard errors
    # beyond r = 7.697 (probability 4.5e-4, ~226 draws, Poisson sd 15) the tail is r + E
    tail = e[e > ZIGGURAT_EXP_R]
    assert abs(tail.size - 5e5 * math.exp(-ZIGGURAT_EXP_R)) < 5 * 15
    assert stats.kstest(tail - ZIGGURAT_EXP_R, "expon").pvalue > 1e-3
