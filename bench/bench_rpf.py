"""Benchmarks of the regularized particle filter (Iglesis & de Montella): speed and memory.

    make bench, or: python -m bench.bench_rpf [--quick]

Prints one line per figure, ``name: value unit``, all measured in this one run:

- particle-steps per second of one tmakit filter (N = 5000, bearings only, the static-observer
  scenario, 151 cycles) and of the batched Monte Carlo (40 runs per call, in blocks of runs, on
  one thread and on 2 threads), with the compiled fused cycle loop (``RpfConfig(engine=
  "kernel"``, the default; `tracker.rpf.kernel`) and, for reference, the numpy implementation;
- the same for Stone Soup's particle filter on the same bearings (ParticlePredictor,
  ParticleUpdater with a MultinomialResampler applied when N_eff < N/3, and the
  MCMCRegulariser), run by the Python of a separate environment holding ``stonesoup``
  (``$STONESOUP_PYTHON``, default .venv-stonesoup/bin/python, made by ``make bench``; Stone Soup
  is not a tmakit dependency), and the speed ratios;
- wall time and peak memory of 1000 runs x 151 cycles x 5000 particles of ``idm-static``
  (bearings only and bearings + SPL) on 2 worker processes (skipped with --quick).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from bench.harness import REPO, Session

session = Session("rpf")

STONESOUP_STEPS = 30

_STONESOUP_CODE = r'''
import json, math, sys, time
import numpy as np
from datetime import datetime, timedelta
from stonesoup.models.transition.linear import (CombinedLinearGaussianTransitionModel,
                                                ConstantVelocity)
from stonesoup.models.measurement.nonlinear import Cartesian2DToBearing
from stonesoup.predictor.particle import ParticlePredictor
from stonesoup.updater.particle import ParticleUpdater
from stonesoup.resampler.particle import MultinomialResampler, ESSResampler
from stonesoup.regulariser.particle import MCMCRegulariser
from stonesoup.types.state import ParticleState
from stonesoup.types.detection import Detection
from stonesoup.types.hypothesis import SingleHypothesis
from stonesoup.types.array import StateVectors

args = json.loads(sys.stdin.read())
n, steps = args["n"], args["steps"]
bearings, init = np.array(args["bearings"]), np.array(args["init"])
sigma_a, dt = args["sigma_a"], args["dt"]
q = sigma_a ** 2  # ConstantVelocity's noise_diff_coeff: the same DWNA covariance for a white
# acceleration of spectral density q is q [[dt^3/3, dt^2/2], [dt^2/2, dt]]; close to ours
trans = CombinedLinearGaussianTransitionModel([ConstantVelocity(q), ConstantVelocity(q)])
# Stone Soup's bearing is atan2(y, x) (counter-clockwise from east): give it (y, x) via the mapping
meas = Cartesian2DToBearing(ndim_state=4, mapping=(2, 0),
                            noise_covar=np.array([[math.radians(args["sigma_deg"]) ** 2]]))
resampler = ESSResampler(threshold=n / 3, resampler=MultinomialResampler())
updater = ParticleUpdater(meas, resampler=resampler,
                          regulariser=MCMCRegulariser(transition_model=trans))
predictor = ParticlePredictor(trans)
t0 = datetime(2024, 1, 1)
# state order (x, vx, y, vy) for Stone Soup's combined model
sv = StateVectors(np.stack([init[0], init[2], init[1], init[3]]))
prior = ParticleState(sv, weight=np.full(n, 1.0 / n), timestamp=t0)
resampled = 0
elapsed = 0.0
for k in range(1, steps + 1):
    ts = t0 + timedelta(seconds=dt * k)
    start = time.perf_counter()
    pred = predictor.predict(prior, timestamp=ts)
    det = Detection(np.array([[bearings[k]]]), timestamp=ts, measurement_model=meas)
    prior = updater.update(SingleHypothesis(pred, det))
    elapsed += time.perf_counter() - start
    # after a resampling the weights are equal again (checked outside the timing)
    w = np.array([float(v) for v in prior.weight])
    resampled += bool(np.allclose(w, 1.0 / n, rtol=1e-6, atol=0))
print(json.dumps({"elapsed_s": elapsed, "steps": steps, "n": n, "resampled": resampled}))
'''




def _scenario():
    from tools.studies.idm_scenarios import get_scenario
    from tracker import rpf

    sc = get_scenario("idm-static")
    t = sc.t_s
    obs = sc.observer_state(t)
    rel = sc.target_state(t) - obs
    rng = np.random.default_rng(1)
    b = rpf.bearing_rad(rel[:, 0], rel[:, 1]) + math.radians(1.5) * rng.standard_normal(t.size)
    return sc, t, obs, b


def bench_tmakit(runs: int, n: int = 5000, threads: int = 1, cycles: int | None = None,
                 repeat: int = 1, engine: str = "kernel") -> float:
    """Particle-steps per second of the tmakit RPF, bearings only, ``runs`` runs per call.

    Over the first ``cycles`` cycles (all by default); the best of ``repeat`` calls.
    """
    from tracker import rpf

    _, t, obs, b = _scenario()
    t, obs, b = t[:cycles], obs[:cycles], b[:cycles]
    cfg = rpf.RpfConfig(n_particles=n, engine=engine)
    best = 0.0
    for i in range(repeat):
        rng = np.random.default_rng(2 + i)
        start = time.perf_counter()
        res = rpf.run_batch(t_s=t, obs_state=obs, bearing_rad_meas=np.tile(b, (runs, 1)),
                            level_db_meas=None, k_profiles=None, cfg=cfg, rng=rng,
                            threads=threads)
        best = max(best, runs * t.size * n / (time.perf_counter() - start))
    if runs == 1 and repeat > 1:
        session.say(f"rpf_{engine}_resampled_fraction_{t.size}_cycles",
            float(res.resampled[:, 1:].mean()))
    return best


def bench_stonesoup(python: str, n: int = 5000) -> float | None:
    """Particle-steps per second of Stone Soup's particle filter, or None if not installed."""
    from tracker import rpf

    if not Path(python).exists():
        return None
    _, t, obs, b = _scenario()
    cfg = rpf.RpfConfig(n_particles=n)
    init = rpf.initial_particles(b[0], obs[0, 2:], cfg, 1, np.random.default_rng(3))[:, 0]
    # Stone Soup measures atan2(y, x) on the (y, x) mapping = our atan2(x, y) bearing
    args = {"n": n, "steps": STONESOUP_STEPS, "bearings": b[: STONESOUP_STEPS + 1].tolist(),
            "init": init.tolist(), "sigma_a": cfg.sigma_a_mps2, "dt": 60.0, "sigma_deg": 1.5}
    proc = subprocess.run([python, "-c", _STONESOUP_CODE], input=json.dumps(args),
                          capture_output=True, text=True)
    if proc.returncode != 0:
        print(proc.stderr[-2000:], file=sys.stderr)
        return None
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    session.say("stonesoup_resampled_fraction_first_30_cycles", out["resampled"] / out["steps"])
    return out["steps"] * out["n"] / out["elapsed_s"]


def bench_full(runs: int = 1000, workers: int = 2) -> tuple[float, float, float]:
    """Wall time (s), peak memory (GiB, largest process) and particle-steps/s of a full study."""
    code = ("import sys; from pathlib import Path; "
            f"from tools.studies import idm as e; import json; "
            f"d = e.run('idm-static', runs={runs}, out_dir=Path(sys.argv[1]), seed=1, "
            f"workers={workers}, grid=sys.argv[2]); "
            f"print(json.dumps({{'elapsed_s': d['elapsed_s'], "
            f"'rate': d['particle_steps_per_s']}}))")
    with tempfile.TemporaryDirectory() as tmp:
        grid = Path(tmp) / "munk-1000.nc"
        subprocess.run([sys.executable, "-m", "tools.cli", "grids", "build", "munk-1000", "--out",
                        str(grid)], cwd=REPO, check=True, capture_output=True)
        start = time.perf_counter()
        with tempfile.TemporaryFile("w+") as out:
            proc = subprocess.Popen([sys.executable, "-c", code, tmp, str(grid)], stdout=out,
                                    cwd=REPO)
            proc.wait()
            wall = time.perf_counter() - start
            out.seek(0)
            data = json.loads(out.read().strip().splitlines()[-1])
    peak_kib = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    return wall, peak_kib / 2**20, data["rate"]


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="skip the 1000-run study")
    parser.add_argument("--stonesoup-python",
                        default=os.environ.get("STONESOUP_PYTHON",
                                               str(REPO / ".venv-stonesoup" / "bin" / "python")))
    args = parser.parse_args(argv)

    start = time.perf_counter()
    bench_tmakit(1, cycles=5)  # warm-up (imports, numba's compile or cache load), not timed
    session.say("rpf_kernel_first_call_incl_compile_or_cache_load", time.perf_counter() - start, "s")
    bench_tmakit(1, cycles=5, engine="numpy")
    one = bench_tmakit(1, repeat=3)
    # the same cycles as Stone Soup is timed on (the first ones, where it resamples more)
    one_30 = bench_tmakit(1, cycles=STONESOUP_STEPS + 1, repeat=3)
    batched = bench_tmakit(40, repeat=2)
    threaded = bench_tmakit(40, threads=2, repeat=2)
    one_np = bench_tmakit(1, repeat=2, engine="numpy")
    batched_np = bench_tmakit(40, engine="numpy")
    session.say("rpf_one_filter_n5000", one / 1e6, "M particle-steps/s")
    session.say("rpf_one_filter_n5000_first_31_cycles", one_30 / 1e6, "M particle-steps/s")
    session.say("rpf_batched_40_runs_n5000", batched / 1e6, "M particle-steps/s")
    session.say("rpf_batched_40_runs_n5000_2_threads", threaded / 1e6, "M particle-steps/s")
    session.say("rpf_numpy_reference_one_filter_n5000", one_np / 1e6, "M particle-steps/s")
    session.say("rpf_numpy_reference_batched_40_runs_n5000", batched_np / 1e6, "M particle-steps/s")
    session.say("speedup_kernel_vs_numpy_one_filter", one / one_np, "x")
    session.say("speedup_kernel_vs_numpy_batched", batched / batched_np, "x")
    ss = bench_stonesoup(args.stonesoup_python)
    if ss is None:
        session.say("stonesoup", "not available", f"(no {args.stonesoup_python})")
    else:
        session.say("stonesoup_particle_filter_n5000", ss / 1e6, "M particle-steps/s")
        session.say("speedup_one_filter_vs_stonesoup", one / ss, "x")
        session.say("speedup_one_filter_same_cycles_vs_stonesoup", one_30 / ss, "x")
        session.say("speedup_batched_vs_stonesoup", batched / ss, "x")
        session.say("speedup_batched_2_threads_vs_stonesoup", threaded / ss, "x")
    if not args.quick:
        wall, peak_gib, rate = bench_full()
        session.say("idm_static_1000runs_151cycles_n5000_bot_and_spl_wall", wall, "s")
        session.say("idm_static_1000runs_peak_memory_largest_process", peak_gib, "GiB")
        session.say("idm_static_1000runs_rate", rate / 1e6, "M particle-steps/s")


if __name__ == "__main__":
    main()
    session.write()
