"""The compiled band sums of the surface's arrivals (``acoustics.builder._lloyd``) against the
formula they compute, exp and sin at every frequency in numpy: the blocked, polynomial kernel
must give the same sums to float rounding, in every branch (the carried attenuation and the
reduced sine, and the library calls a block falls back to). And each receiver depth's band
quadrature."""

from __future__ import annotations

import numpy as np

from acoustics.builder._lloyd import BLOCK, LARGE_PHASE, SMALL_EXPONENT, band_sums


def reference(attenuation, depth_m, speed_mps, angle_deg, freqs_hz, ratio, weights):
    a = np.exp(np.outer(np.log(np.maximum(attenuation, 1e-300)), ratio))            # (n, f)
    # the phase per Hz, then times f, as the kernel forms it: a sine's argument near 1e5 rad
    # rounded another way moves it by 1e-11
    phase = 2.0 * np.pi * np.sin(np.radians(angle_deg)) * depth_m / speed_mps
    g = 2.0 * np.sin(np.outer(phase, freqs_hz)) ** 2                                # (n, f)
    return a @ weights.T, (a * g) @ weights.T                                       # (n, class)


def arrivals(rng, n, *, log_a_max, depth_max_m):
    return (np.exp(-rng.uniform(0.0, log_a_max, n)), rng.uniform(0.5, depth_max_m, n),
            rng.uniform(1480.0, 1540.0, n), rng.uniform(-80.0, 80.0, n))


def test_the_blocked_sums_are_the_formula_to_float_rounding(rng):
    # a band of 161 frequencies, 1000-3000 Hz, three classes; 3 blocks and a part
    freqs = np.geomspace(1000.0, 3000.0, 161)
    ratio = np.linspace(1.0, 3.0, 161) ** 2
    weights = rng.dirichlet(np.ones(161), size=3)
    n = 3 * BLOCK + 17
    for log_a_max, depth_max in ((0.05, 70.0),    # the shelf-break radials: carried, reduced
                                 (50.0, 70.0),    # a lossy path: exp at every frequency
                                 (0.05, 2e4)):    # a phase beyond LARGE_PHASE: sin itself
        args = (*arrivals(rng, n, log_a_max=log_a_max, depth_max_m=depth_max), freqs, ratio, weights)
        plain, lloyd = band_sums(*args)
        want_plain, want_lloyd = reference(*args)
        np.testing.assert_allclose(plain.T, want_plain, rtol=1e-12, atol=0)
        np.testing.assert_allclose(lloyd.T, want_lloyd, rtol=1e-11, atol=1e-300)
    # the cases above reach each branch
    assert 0.05 * (ratio[-1] - ratio[-2]) <= SMALL_EXPONENT < 50.0 * (ratio[-1] - ratio[-2])
    assert 2 * np.pi * 70.0 / 1480.0 * 3000.0 <= LARGE_PHASE < 2 * np.pi * 1e4 / 1540.0 * 3000.0


def test_each_receiver_depth_takes_the_quadrature_its_turns_need_up_to_the_bands_reach():
    import envdata
    from acoustics.builder.imageruns import IMAGE_MIN_POINTS, IMAGE_POINTS_PER_TURN, surface_image
    from acoustics.surface import band_quadrature, surface_reach_m

    area = envdata.load_area("shelf-break")
    depths = np.array([0.0, 2.5, 10.0, 50.0, 300.0])
    image = surface_image(area, float(area.bands[0].center_hz), depths, np.full(depths.size, 1500.0))
    for ib, band in enumerate(area.bands):
        n = [len(row[ib].freqs_hz) for row in image.bands]
        reach_n = band_quadrature(area.classes[0], band, surface_reach_m(band, 1500.0), 1500.0,
                                  points_per_turn=IMAGE_POINTS_PER_TURN, min_points=IMAGE_MIN_POINTS)[0].size
        # more turns deeper, never more than the band's reach asks for (the factor averages out below it)
        assert n == sorted(n) and max(n) == reach_n and n[-1] == reach_n, (band.name, n, reach_n)
        assert n[0] < reach_n  # the surface row: the fewest
        for row in image.bands:  # each class's weights sum to 1 over that row's frequencies
            assert np.allclose([sum(w) for w in row[ib].weights], 1.0)
