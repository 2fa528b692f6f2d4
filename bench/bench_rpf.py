"""Benchmarks of the regularized particle filter (Iglesis & de Montella): speed and memory.

    make bench, or: python -m bench.bench_rpf [--quick]

Prints one line per figure, ``name: value unit``, all measured in this one run, and writes
docs/results/rpf.json:

- particle-steps per second of one tmakit filter (N = 5000, bearings only, the static-observer
  scenario, 151 cycles, and its first 31) and of the batched Monte Carlo (40 runs per call, in
  blocks of runs, on one thread and on 2 threads), with the compiled fused cycle loop
  (``RpfConfig(engine="kernel")``, the default; `tracker.rpf.kernel`) and, for reference, the
  numpy implementation, with the filters' resampling fractions;
- wall time and peak memory of 1000 runs x 151 cycles x 5000 particles of ``idm-static``
  (bearings only and bearings + SPL) on 2 worker processes (skipped with --quick).

Stone Soup's particle filter on the same bearings, side by side with this filter, is
bench/bench_stonesoup.py's (docs/results/stonesoup.json), which takes `bench_tmakit` from here.
"""

from __future__ import annotations

import argparse
import json
import math
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from bench.harness import REPO, Session


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
                 repeat: int = 1, engine: str = "kernel") -> tuple[float, float]:
    """Particle-steps per second of the tmakit RPF, bearings only, ``runs`` runs per call, and the
    share of its cycles (after the first) that resampled.

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
    return best, float(res.resampled[:, 1:].mean())


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
    args = parser.parse_args(argv)
    session = Session("rpf")

    start = time.perf_counter()
    bench_tmakit(1, cycles=5)  # warm-up (imports, numba's compile or cache load), not timed
    session.say("rpf_kernel_first_call_incl_compile_or_cache_load", time.perf_counter() - start, "s")
    bench_tmakit(1, cycles=5, engine="numpy")
    one, resampled = bench_tmakit(1, repeat=3)
    session.say("rpf_kernel_resampled_fraction_151_cycles", resampled)
    # the first cycles, where it resamples more (the window Stone Soup is timed on)
    one_31, resampled = bench_tmakit(1, cycles=31, repeat=3)
    session.say("rpf_kernel_resampled_fraction_31_cycles", resampled)
    batched, _ = bench_tmakit(40, repeat=2)
    threaded, _ = bench_tmakit(40, threads=2, repeat=2)
    one_np, resampled = bench_tmakit(1, repeat=2, engine="numpy")
    session.say("rpf_numpy_resampled_fraction_151_cycles", resampled)
    batched_np, _ = bench_tmakit(40, engine="numpy")
    session.say("rpf_one_filter_n5000", one / 1e6, "M particle-steps/s")
    session.say("rpf_one_filter_n5000_first_31_cycles", one_31 / 1e6, "M particle-steps/s")
    session.say("rpf_batched_40_runs_n5000", batched / 1e6, "M particle-steps/s")
    session.say("rpf_batched_40_runs_n5000_2_threads", threaded / 1e6, "M particle-steps/s")
    session.say("rpf_numpy_reference_one_filter_n5000", one_np / 1e6, "M particle-steps/s")
    session.say("rpf_numpy_reference_batched_40_runs_n5000", batched_np / 1e6, "M particle-steps/s")
    session.say("speedup_kernel_vs_numpy_one_filter", one / one_np, "x")
    session.say("speedup_kernel_vs_numpy_batched", batched / batched_np, "x")
    session.say("speedup_2_threads_vs_1_batched", threaded / batched, "x")
    if not args.quick:
        wall, peak_gib, rate = bench_full()
        session.say("idm_static_1000runs_151cycles_n5000_bot_and_spl_wall", wall, "s")
        session.say("idm_static_1000runs_peak_memory_largest_process", peak_gib, "GiB")
        session.say("idm_static_1000runs_rate", rate / 1e6, "M particle-steps/s")
    session.write()


if __name__ == "__main__":
    main()
