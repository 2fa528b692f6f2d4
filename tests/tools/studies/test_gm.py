"""The paper's experiment on a reduced design (3^3 runs) against its conclusions."""

from pathlib import Path

import pytest

import acoustics
import envdata
from tools.studies.gm import design, run


@pytest.fixture(scope="session")
def ocean_grid_file(tmp_path_factory):
    grid = acoustics.build_grid(envdata.load_area("ocean-deep"), model="bellhop")
    path = tmp_path_factory.mktemp("gm") / "ocean-deep.nc"
    acoustics.write_grid(grid, path)
    return path


def test_design_weights_eqs_32_34():
    from envdata import TargetClass

    cls = TargetClass(name="TV", depth_m=8.0, speed_mean_mps=7.5, speed_sd_mps=1.0,
                      noise_mean_db=133.0, noise_sd_db=2.5, k_error_sd_db=1.5)
    dv, dp, dk, w = design(cls, 11)
    assert len(dv) == 1331 and dv.max() == pytest.approx(2.0) and dp.min() == pytest.approx(-5.0)
    assert w.max() == pytest.approx(1.0) and w.argmax() == 665  # the centre node


@pytest.fixture(scope="module")
def tv_30km_paper(ocean_grid_file, tmp_path_factory):
    """gm-tv-30km on the reduced design with the paper's tests (the experiment's default,
    `PAPER_PARAMS`), seed 1: read by the paper's conclusions and by the manoeuvre tests'
    comparison below."""
    out = tmp_path_factory.mktemp("gm-tv-30km")
    return run("gm-tv-30km", grid_path=ocean_grid_file, n=3, out_dir=out, seed=1), out


@pytest.mark.slow
@pytest.mark.bellhop
def test_tv_30km_reduced_design_meets_the_paper(tv_30km_paper):
    res, tmp_path = tv_30km_paper
    s = res["steady_state"]
    tv = s["TV"]
    # paper's conclusion 3 (30 km): course 5-7 deg, speed 1.0-1.5 m/s, range 2-3 km.
    # Upper bounds with a 30 % margin for a 27-run design (27 runs give 4.8 deg, 1.03 m/s,
    # 3.25 km with this seed, 3.19 km with seed 0; 1331 runs: 5.1 deg, 0.98 m/s, 3.06 km).
    assert res["center"] == "class"
    assert tv["course_rms_deg"] < 7.0 * 1.3
    assert tv["speed_rms_mps"] < 1.5 * 1.3
    assert tv["range_rms_m"] < 3000.0 * 1.3
    # conclusion 1: the true-class hypothesis has the smallest errors (range and speed)
    assert tv["range_rms_m"] < s["NPS"]["range_rms_m"]
    assert tv["speed_rms_mps"] < s["NPS"]["speed_rms_mps"]
    assert (tmp_path / "rms.csv").exists() and (tmp_path / "rms.png").exists()
    assert sorted(Path(f).name for f in res["plots"]) == ["rms.png", "run.png"]
    # the stated sds are checked after 10 min, over the run and per true tack
    cal = res["calibration_after_late_min"]
    assert set(cal) == {"all", "tack_1", "tack_2"}
    assert all(0.0 <= cal["all"][q]["coverage_90"] <= 1.0 for q in ("course", "speed", "range"))
    assert (tmp_path / "run.png").stat().st_size > 10_000   # a drawn figure, not an empty one


@pytest.mark.slow
@pytest.mark.bellhop
def test_tv_110km_reduced_design_meets_the_paper(ocean_grid_file, tmp_path):
    res = run("gm-tv-110km", grid_path=ocean_grid_file, n=3, out_dir=tmp_path, seed=0)
    s = res["steady_state"]
    tv = s["TV"]
    # paper's conclusion 4 (110 km): course 5-30 deg, range within 20 %, speed error about the
    # class sd (1.0 m/s). 30 % margin for a 27-run design (docs/gm.md: 9.3 deg, 0.93 m/s, 19 %)
    assert tv["course_rms_deg"] < 30.0 * 1.3
    assert tv["speed_rms_mps"] < 1.0 * 1.3
    assert tv["range_rms_rel"] < 0.20 * 1.3
    # conclusion 1: the true-class hypothesis has the smallest errors
    for other in ("SW", "NPS"):
        assert tv["course_rms_deg"] < s[other]["course_rms_deg"]
        assert tv["range_rms_m"] < s[other]["range_rms_m"]


def test_design_centre_is_the_class_distribution():
    from envdata import TargetClass
    from tools.studies.gm import center_offsets
    from tracker.scenario import load_scenario

    cls = TargetClass(name="TV", depth_m=8.0, speed_mean_mps=7.5, speed_sd_mps=1.0,
                      noise_mean_db=133.02, noise_sd_db=2.5, k_error_sd_db=1.5)
    sc = load_scenario("gm-tv-30km")
    # eqs. 32-34 weight by the class PDFs: the first tack (6.5 m/s, 131.02 dB) moves to the
    # class means; the second keeps its +2 m/s, +4 dB change
    dv, dp = center_offsets(sc, cls, "class")
    assert dv == pytest.approx(1.0) and dp == pytest.approx(2.0)
    assert center_offsets(sc, cls, "scenario") == (0.0, 0.0)
    with pytest.raises(ValueError, match="center"):
        center_offsets(sc, cls, "median")


@pytest.mark.slow
@pytest.mark.bellhop
def test_progress_bar_on_stderr(ocean_grid_file, tmp_path, capfd):
    res = run("gm-tv-30km", grid_path=ocean_grid_file, n=1, out_dir=tmp_path, progress=True)
    assert res["runs"] == 1
    err = capfd.readouterr().err
    assert "gm gm-tv-30km" in err and "1/1" in err


def test_rms_skips_runs_without_an_estimate():
    import numpy as np

    from tools.studies.gm import weighted_rms

    # 1 class, 3 runs, 2 cycles; run 0 has no range estimate in cycle 0 (not yet detected)
    sq = {"range": np.array([[[np.nan, 4.0], [1.0, 1.0], [9.0, 9.0]]])}
    rms, runs = weighted_rms(sq, [2.0, 1.0, 1.0])
    # eqs. 32-34 over the runs that have an estimate: cycle 0 sqrt((1 + 9) / 2), cycle 1 all
    assert rms["range"][0, 0] == pytest.approx(np.sqrt(5.0))
    assert rms["range"][0, 1] == pytest.approx(np.sqrt((2 * 4.0 + 1.0 + 9.0) / 4.0))
    assert runs["range"].tolist() == [[2, 3]]
    rms, runs = weighted_rms({"range": np.full((1, 2, 1), np.nan)}, [1.0, 1.0])
    assert np.isnan(rms["range"][0, 0]) and runs["range"][0, 0] == 0


@pytest.mark.slow
@pytest.mark.bellhop
def test_numbers_do_not_depend_on_the_worker_count(ocean_grid_file, tmp_path):
    # 8 runs in 3 chunks of 3, 3 and 2 runs
    one = run("gm-nps", grid_path=ocean_grid_file, n=2, out_dir=tmp_path / "1", seed=4, workers=1,
              chunk_runs=3)
    two = run("gm-nps", grid_path=ocean_grid_file, n=2, out_dir=tmp_path / "2", seed=4, workers=2,
              chunk_runs=3)
    assert one["steady_state"] == two["steady_state"]
    assert (tmp_path / "1" / "rms.csv").read_text() == (tmp_path / "2" / "rms.csv").read_text()


@pytest.mark.slow
@pytest.mark.bellhop
def test_the_default_manoeuvre_tests_are_as_quick_as_the_papers(ocean_grid_file, tv_30km_paper, tmp_path):
    """gm-tv-30km: the transport turns and speeds up (+4 dB) at 20 min. The robust tests of
    ``tmakit track`` (quiet on the follow study's straight target) declare it as soon as the
    paper's, and the true class's figures stay within 5 % of the paper's tests' on both tacks.
    (Before: the class's K error joined to sigma_dW hid the +4 dB, the turn was never declared
    and the second tack's course RMS was 18 deg against 1.9.)"""
    from tracker.mltma import MLParams

    res = {"paper": tv_30km_paper[0],
           "default": run("gm-tv-30km", grid_path=ocean_grid_file, n=3, out_dir=tmp_path, seed=1, params=MLParams())}
    for name in res:
        turn = res[name]["manoeuvres"][1]
        assert turn["from_s"] == 1200.0 and turn["missed_runs"] == 0 and turn["delay_s"]["max"] <= 30.0
        assert sum(item["false_per_run"] for item in res[name]["manoeuvres"]) == 0.0
    for tack in ("steady_state", "later_tacks"):
        paper, default = (res[k][tack] if tack == "steady_state" else res[k][tack][0] for k in ("paper", "default"))
        for key in ("course_rms_deg", "speed_rms_mps", "range_rms_m"):
            assert default["TV"][key] == pytest.approx(paper["TV"][key], rel=0.05)


def test_weighted_calibration_counts_the_weighted_share_inside_the_interval():
    import numpy as np

    from tools.studies.gm import weighted_calibration

    t = np.arange(0.0, 1800.0, 60.0)                     # 30 cycles, 10 min on from cycle 10
    z = {"range": np.zeros((2, t.size)), "course": np.zeros((2, t.size)), "speed": np.zeros((2, t.size))}
    z["range"][0] = 3.0                                   # run 0 always outside 1.645, run 1 inside
    cal = weighted_calibration(z, np.array([1.0, 3.0]), t, np.ones(t.size, dtype=int))
    assert cal["all"]["range"]["coverage_90"] == 0.75 and cal["all"]["range"]["median_abs_z"] == 0.0
    assert cal["all"]["range"]["mean_sq_z"] == 2.25 and cal["tack_1"] == cal["all"]
