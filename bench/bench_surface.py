"""What the surface at the target's end costs: the default (semicoherent) build against the
incoherent beams it replaced, side by side in one run (DESIGN.md "Near-surface sources and the
beam fan"; target: <= 2x the build time).

``python -m bench.bench_surface [--repeats N]`` writes ``docs/results/surface-cost.json``.
Three builds, each in both modes, interleaved, ``--repeats`` times, 2 worker threads, no resume
folder:

- ocean-deep's flat grid (source at each class's depth; the ships' runs carry their Lloyd pattern:
  the same runs, so the same cost but for the pattern file);
- shelf-break's bearing-dependent grid (12 radials from the observer; each radial adds its
  arrivals run, 6000 beams at the near-surface depths);
- one atlas table of shelf-break-atlas (its first position and month: a bearing-dependent grid
  on the atlas's depth axis).

Reported: the medians of wall time and of the summed BELLHOP process time, and their ratios.
"""

from __future__ import annotations

import argparse
import dataclasses

import numpy as np

from bench.harness import Session, median


def _areas() -> dict:
    import envdata
    from acoustics.builder.atlas import atlas_depth_axis_m, plan_atlas
    from envdata.atlasarea import table_area

    atlas_area = envdata.load_area("shelf-break-atlas")
    plan = plan_atlas(atlas_area)
    table = table_area(atlas_area, plan.months[0], float(plan.lat_deg[0]), float(plan.lon_deg[0]))
    def atlas_axis(area, deepest_m):  # the atlas's own depth axis, as its build gives the table
        return atlas_depth_axis_m(atlas_area, deepest_m)

    return {"ocean-deep": (envdata.load_area("ocean-deep"), None),
            "shelf-break": (envdata.load_area("shelf-break"), None),
            "atlas table": (table, atlas_axis)}


def _with_mode(area, mode):
    import envdata

    return dataclasses.replace(area, propagation=dataclasses.replace(area.propagation, mode=envdata.TlMode(mode)))


def _build(area, depth_rule, stats_out: list):
    import acoustics
    from acoustics.builder.radial import build_radial_grid, depth_axis_m
    from envdata.radials import area_radials

    stats = acoustics.BuildStats()
    if depth_rule is None:
        acoustics.build_grid(area, workers=2, stats=stats)
    else:  # an atlas table: its radials, the atlas's own depth axis
        radials = area_radials(area)
        depth = depth_rule(area, float(depth_axis_m(area, radials)[-1]))
        build_radial_grid(area, workers=2, stats=stats, radials=radials, depth_m=depth)
    stats_out.append((stats.bellhop_seconds, stats.runs_total))


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--only", nargs="*", help="builds to measure (default: all)")
    args = p.parse_args(argv)
    session = Session("surface-cost")
    builds = {}
    for name, (area, rule) in _areas().items():
        if args.only and name not in args.only:
            continue
        for mode in ("incoherent", "semicoherent"):
            builds[(name, mode)] = (_with_mode(area, mode), rule)
    bellhop = {key: [] for key in builds}
    times = session.interleave({f"{n} {m}": (lambda key=(n, m): _build(*builds[key], bellhop[key]))
                                for n, m in builds}, args.repeats)
    table = {}
    for name in dict.fromkeys(n for n, _ in builds):
        inc, semi = times[f"{name} incoherent"], times[f"{name} semicoherent"]
        b_inc = [b for b, _ in bellhop[(name, "incoherent")]]
        b_semi = [b for b, _ in bellhop[(name, "semicoherent")]]
        table[name] = {"wall_incoherent_s": round(median(inc), 2), "wall_semicoherent_s": round(median(semi), 2),
                       "wall_ratio": round(median(semi) / median(inc), 2),
                       "bellhop_incoherent_s": round(median(b_inc), 2),
                       "bellhop_semicoherent_s": round(median(b_semi), 2),
                       "bellhop_ratio": round(median(b_semi) / median(b_inc), 2),
                       "runs_incoherent": bellhop[(name, "incoherent")][0][1],
                       "runs_semicoherent": bellhop[(name, "semicoherent")][0][1]}
        session.say(f"{name} wall semicoherent / incoherent", table[name]["wall_ratio"], "x",
                    runs=np.array(semi) / np.array(inc))
        session.say(f"{name} BELLHOP semicoherent / incoherent", table[name]["bellhop_ratio"], "x")
    session.write(repeats=args.repeats, builds=table)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
