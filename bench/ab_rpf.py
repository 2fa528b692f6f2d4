"""Compare the compiled particle filter's speed under several Python environments, interleaved.

    python -m bench.ab_rpf PYTHON_A PYTHON_B [PYTHON_C ...] [--rounds 6] [--name NAME]

For comparing dependency sets (numpy/numba versions) on a shared, noisy machine. Each round runs
one measuring process per environment, forwards then backwards (A B C, C B A, A B C, ...), so
that drift in the machine's load falls on all. An environment needs only numpy and numba. A
process times the kernel (`tracker.rpf_kernel`, via
``rpf.run_batch``) on the bench's idm-static bearings, N = 5000, 151 cycles: one filter (best of
5) and 40 runs in one call on one thread (best of 2), in particle-steps per second of wall time
and per second of the process's CPU time. CPU time is the figure that other users' load
changes least. Both environments run this checkout's code (on their PYTHONPATH). With --name,
written to docs/results/NAME.json by the harness. Not part of ``make bench``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

from bench.harness import REPO, git_state, load_average, provenance, write_result

_CHILD = r'''
import json, time
import numba
import numpy as np
from bench.bench_rpf import _scenario
from tracker import rpf

_, t, obs, b = _scenario()
cfg = rpf.RpfConfig(n_particles=5000)


def rate(runs, seed):
    rng = np.random.default_rng(seed)
    wall0, cpu0 = time.perf_counter(), time.process_time()
    res = rpf.run_batch(t_s=t, obs_state=obs, bearing_rad_meas=np.tile(b, (runs, 1)),
                        level_db_meas=None, k_profiles=None, cfg=cfg, rng=rng, threads=1)
    wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
    steps = runs * t.size * cfg.n_particles
    return steps / wall / 1e6, steps / cpu / 1e6


rate(1, 0)  # compile or load numba's cache, not timed
out = {"numpy": np.__version__, "numba": numba.__version__}
for name, runs, repeat in (("one", 1, 5), ("batched40", 40, 2)):
    rates = [rate(runs, 2 + i) for i in range(repeat)]
    out[name + "_wall"] = max(r[0] for r in rates)
    out[name + "_cpu"] = max(r[1] for r in rates)
print(json.dumps(out))
'''

FIGURES = ("one_wall", "one_cpu", "batched40_wall", "batched40_cpu")


def measure(python: str, cache_dir: Path) -> dict:
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache_dir))  # one numba cache per environment
    env["PYTHONPATH"] = str(REPO)  # this checkout's code, whatever the environment installs
    proc = subprocess.run([python, "-c", _CHILD], capture_output=True, text=True, env=env, cwd=REPO, check=True)
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("pythons", nargs="+", metavar="PYTHON")
    parser.add_argument("--rounds", type=int, default=6)
    parser.add_argument("--cache-root", type=Path, default=Path("/tmp/tmakit-ab-numba-cache"))
    parser.add_argument("--name", help="also write docs/results/NAME.json")
    args = parser.parse_args(argv)
    load_before, git = load_average(), git_state()
    labels = [chr(ord("A") + i) for i in range(len(args.pythons))]
    pythons = dict(zip(labels, args.pythons))
    results: dict[str, list[dict]] = {label: [] for label in labels}
    for i in range(args.rounds):
        for label in labels if i % 2 == 0 else labels[::-1]:
            out = measure(pythons[label], args.cache_root / label)
            results[label].append(out)
            print(f"{label} numpy {out['numpy']} numba {out['numba']}: "
                  + ", ".join(f"{k} {out[k]:.2f}" for k in FIGURES), flush=True)
    medians = {label: {k: statistics.median(r[k] for r in results[label]) for k in FIGURES}
               for label in labels}
    for label in labels:
        out = results[label][0]
        print(f"median {label} (numpy {out['numpy']}, numba {out['numba']}): "
              + ", ".join(f"{k} {medians[label][k]:.2f}" for k in FIGURES)
              + " M particle-steps/s; vs A: "
              + ", ".join(f"{medians[label][k] / medians['A'][k]:.3f}" for k in FIGURES))
    if args.name:
        write_result(args.name, {"pythons": pythons, "rounds": args.rounds, "runs": results,
                                 "medians_m_particle_steps_per_s": medians},
                     provenance_data=provenance(load_before=load_before, git=git))
    return 0


if __name__ == "__main__":
    sys.exit(main())
