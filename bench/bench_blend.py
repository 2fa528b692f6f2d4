"""How an atlas's tables are blended between positions, tried on the follow study
(docs/atlas-tracking.md): the bilinear weights alone and tempered by the water depth
(``acoustics.grid.atlas.weights.water_weights``) with ratios 2 and 3, the ML analysis and the
particle filter on BELLHOP's levels along the true paths, two seeds of 40 runs; written to
docs/results/atlas-tracking/blend.json.

    python -m bench.bench_blend [--runs 40] [--seeds 7 11]

The grid and atlases are those of the follow study (docs/results/atlas-tracking/grids/, built
or reused).
"""

from __future__ import annotations

import argparse

from bench.harness import REPO, Session
from tools.studies import follow


def main(argv=None) -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=40)
    ap.add_argument("--seeds", type=int, nargs="+", default=[7, 11])
    args = ap.parse_args(argv)
    session = Session("atlas-tracking/blend")
    res = follow.blend_trial(runs=args.runs, seeds=args.seeds, ratios=(None, 2.0, 3.0),
                             out_dir=REPO / "docs" / "results" / "atlas-tracking")
    for key, by_seed in res["scores"].items():
        for seed, figures in by_seed.items():
            session.say(f"{key} seed {seed}", figures["rmse_after_10min_m"], "m")
    session.write(**res)


if __name__ == "__main__":
    main()
