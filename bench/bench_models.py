"""RAM against BELLHOP on the bearing-dependent shelf-break grid: time, memory, workers scaling.

``python -m bench.bench_models [--range-km R] [--bands FB1,FB2] [--repeats N]`` writes
docs/results/models.json.

The shelf-break area's 12 radials, cut to ``--bands`` and ``--range-km`` (the area file's own
30 km and FB1-FB2 are the issue's target; RAM's cost grows as f^2 x depth x range, so on a
shared 2-core machine the defaults are FB1 to 3 km; docs/models.md scales the measured cost to
the full build). Each build is ``tmakit grids build
--json`` in a child process (``bench.harness.cli_with_rusage``: wall time and the peak resident
size of the largest process, the RAM worker processes included), ``--force`` so that nothing is
reused: BELLHOP on 2 workers, RAM on 1 worker and on 2, side by side in one run, repeated,
medians.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
from pathlib import Path

import envdata
from bench.harness import Session, cli_with_rusage

session = Session("models")


def cut_area(folder: Path, *, range_km: float, bands: list[str]) -> Path:
    """shelf-break cut to ``bands`` and ``range_km``, its data files named by absolute path."""
    source = envdata.area_path("shelf-break")
    text = source.read_text().replace('"data/', f'"{source.parent / "data"}/')
    text = text.replace("range_max_m = 30000.0", f"range_max_m = {range_km * 1000.0}")
    lines, out, block = text.splitlines(keepends=True), [], None
    for line in lines + ["[end]\n"]:  # a [[bands]] table runs to the next table header
        if line.startswith("["):
            if block is not None and any(f'name = "{name}"' in "".join(block) for name in bands):
                out.extend(block)
            block = [line] if line.strip() == "[[bands]]" else None
            if block is None and line != "[end]\n":
                out.append(line)
        elif block is not None:
            block.append(line)
        else:
            out.append(line)
    text = "".join(out)
    path = folder / "shelf-cut.toml"
    path.write_text(text)
    area = envdata.load_area(path)
    if [b.name for b in area.bands] != bands:
        raise SystemExit(f"bench: the cut area has bands {[b.name for b in area.bands]}, not {bands}")
    return path


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--range-km", type=float, default=3.0)
    p.add_argument("--bands", default="FB1")
    p.add_argument("--repeats", type=int, default=1)
    args = p.parse_args(argv)
    bands = args.bands.split(",")
    times: dict[str, list[float]] = {"bellhop_w2": [], "ram_w1": [], "ram_w2": []}
    rss: dict[str, list[float]] = {k: [] for k in times}
    ram_seconds: list[float] = []
    with tempfile.TemporaryDirectory() as tmp:
        area = cut_area(Path(tmp), range_km=args.range_km, bands=bands)
        builds = {"bellhop_w2": ("bellhop", "2"), "ram_w1": ("ram", "1"), "ram_w2": ("ram", "2")}
        order = list(builds)
        for i in range(args.repeats):
            for which in order[i % 3:] + order[:i % 3]:  # rotate: no figure always runs first
                model, workers = builds[which]
                wall, peak, info = cli_with_rusage(["grids", "build", str(area), "--model", model, "--workers",
                                                    workers, "--out", str(Path(tmp) / f"{which}.nc"), "--force"])
                times[which].append(wall)
                rss[which].append(peak)
                if which == "ram_w1":
                    ram_seconds.append(info["ram_seconds"])
                    session.say("ram_runs", info["runs"], "RAM runs")
                    session.say("dims", str(info["dims"]))
    med = {k: statistics.median(v) for k, v in times.items()}
    for k in times:
        session.say(f"{k}_wall", med[k], "s", runs=times[k])
        session.say(f"{k}_peak_rss", max(rss[k]), "MiB", runs=rss[k])
    session.say("ram_run_seconds_sum_w1", statistics.median(ram_seconds), "s", runs=ram_seconds)
    session.say("ram_w2_over_bellhop_w2", med["ram_w2"] / med["bellhop_w2"], "x")
    session.say("ram_speedup_2_vs_1", med["ram_w1"] / med["ram_w2"], "x (target >= 1.8)")
    session.write(area="shelf-break, 12 radials", bands=bands, range_km=args.range_km, repeats=args.repeats)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
