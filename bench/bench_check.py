"""``tmakit grids check`` on the built-in areas: how far K moves when the beams, the ray step and
the frequencies per band are doubled (and a run per frequency replaces one per band), on each
area's sample of radials (DESIGN.md "Near-surface sources and the beam fan").

``python -m bench.bench_check [AREA ...]`` writes ``docs/results/grids-check.json`` (default: the
built-in areas but munk-1000, whose fan is BELLHOP's own automatic count).
"""

from __future__ import annotations

import argparse
import dataclasses

from bench.harness import Session

AREAS = ("ocean-deep", "shelf-break")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("areas", nargs="*", default=list(AREAS))
    p.add_argument("--workers", type=int, default=2)
    args = p.parse_args(argv)
    import envdata
    from acoustics.builder.check import check_area

    session = Session("grids-check")
    out = {}
    for name in args.areas:
        area = envdata.load_area(name)
        result = check_area(area, workers=args.workers)
        out[name] = dataclasses.asdict(result)
        for v in result.variants:
            session.say(f"{name} {v.name}", v.median_db,
                        f"dB median |dK| ({v.change}; worst {v.worst_db} dB {v.worst})")
    session.write(areas=out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
