"""The studies' range prior: each run's centre drawn so that its true first range is a draw from
the prior, as an operator's guess would be (`tools.studies.trackerrors.prior_centres_m`)."""

from __future__ import annotations

import numpy as np

from tools.studies.trackerrors import PRIOR_RANGE_SD_FRACTION, prior_centres_m, rpf_config, run_prior


def test_the_true_first_range_is_a_draw_from_each_runs_prior():
    truth = np.full(40_000, 12_000.0)
    centre = prior_centres_m(truth, seed=3)
    z = (truth - centre) / (PRIOR_RANGE_SD_FRACTION * centre)
    # a prior N(m, f m) holds its own draws in 90 % at +-1.645 sd, median |z| 0.674; 40 000 draws
    # put the share within 0.3 % (3 standard errors) and the clip at 3 sd takes 0.3 % of them
    assert 0.895 < np.mean(np.abs(z) <= 1.645) < 0.905
    assert abs(np.median(np.abs(z)) - 0.674) < 0.01
    assert np.all(centre > 0) and np.max(centre / truth) <= 4.0 + 1e-9


def test_every_tracker_of_a_study_starts_a_run_from_the_same_prior():
    truth = np.linspace(8_000.0, 20_000.0, 12)
    a, b = prior_centres_m(truth, seed=(0, 1, 2)), prior_centres_m(truth, seed=(0, 1, 2))
    np.testing.assert_array_equal(a, b)
    assert not np.allclose(a, prior_centres_m(truth, seed=(0, 1, 3)))
    # a run's draw (in sds of its prior) is the run's own, whatever the ranges
    np.testing.assert_allclose(truth / a, 2.0 * truth / prior_centres_m(2.0 * truth, seed=(0, 1, 2)))


def test_run_prior_moves_only_the_range_prior():
    class Sim:  # the two fields `rpf_config` reads of a simulated batch
        range_m = np.full((3, 5), 10_000.0)
        bearing_sigma_deg = np.full((3, 5), 0.1)

    class Cls:
        k_error_sd_db, speed_mean_mps, speed_sd_mps = 2.0, 5.0, 1.0

    class Tables:
        classes = [Cls()]

    cfg = rpf_config(Tables(), Sim(), 0, 100, 1.1)
    moved = run_prior(cfg, 14_000.0)
    assert (moved.range_mean_m, moved.range_sd_m) == (14_000.0, PRIOR_RANGE_SD_FRACTION * 14_000.0)
    assert moved.speed_mean_mps == cfg.speed_mean_mps and moved.n_particles == cfg.n_particles
