"""docs/gm.md: the Grinenkov & Mashoshin experiments and the manoeuvre tests."""

from __future__ import annotations

from pathlib import Path

from bench.docfigures.common import caption, figure, load_result, markdown_table

PAGE = "docs/gm.md"


#: The G&M experiments of docs/gm.md: (result folder, what the paper gives for the true class).
GM_RUNS = (("gm-tv-30km", "5-7 deg, 1.0-1.5 m/s, 2-3 km"), ("gm-tv-110km", "5-30 deg, sV = 1.0 m/s, <= 20 %"),
           ("gm-nps", "Figs. 12-14"))


def gm_experiments(root: Path) -> str:
    rows = [("scenario, runs", "hypothesis", "course RMS", "speed RMS", "range RMS", "paper"), ("---",) * 6]
    sources = []
    for folder, paper in GM_RUNS:
        d = load_result(root, f"{folder}/summary.json")
        true = d["true_class"]
        for name in [true] + [c for c in d["classes"] if c != true]:
            s = d["steady_state"][name]
            cells = (f"{s['course_rms_deg']:.1f} deg", f"{s['speed_rms_mps']:.2f} m/s",
                     f"{s['range_rms_m'] / 1000:.2f} km ({100 * s['range_rms_rel']:.0f} %)")
            if name == true:
                rows.append((f"{folder}, {d['runs']}", f"**{name} (true)**", *(f"**{c}**" for c in cells), paper))
            else:
                rows.append((f"{folder}, {d['runs']}", name, *cells, "larger than true class"))
        sources.append(caption(d, f"{folder}/summary.json"))
    return markdown_table(rows) + "\n" + "".join(sources)


def manoeuvres(root: Path) -> str:
    d = load_result(root, "maneuver.json")
    rows = [("tests", "course, 5-20 min", "speed", "range", "course, 25-40 min", "speed", "range",
             "turn declared after (mean, max)", "missed", "declared where none"), ("---",) * 10]
    for label, name in (("paper", "paper (eqs. 26-29)"), ("default", "default")):
        def f(key: str, label: str = label) -> float:
            return figure(d, f"gm_{label}_{key}")

        rows.append((name, f"{f('tack1_course_rms'):.2f} deg", f"{f('tack1_speed_rms'):.2f} m/s",
                     f"{f('tack1_range_rms'):.0f} m", f"{f('tack2_course_rms'):.2f} deg",
                     f"{f('tack2_speed_rms'):.2f} m/s", f"{f('tack2_range_rms'):.0f} m",
                     f"{f('turn_delay_mean'):.0f} s, {f('turn_delay_max'):.0f} s", f"{f('turn_missed_runs'):d}",
                     f"{f('false_per_run'):.2g} per run"))
    ratios = [figure(d, k) for k in (d.get("figures") or {}) if k.startswith("gm_default_over_paper_")]
    return (markdown_table(rows) + f"\nDefault over paper: {min(ratios):.4f}-{max(ratios):.4f} on the six figures; "
            f"the study took {figure(d, 'gm_default_seconds'):.0f} s with the default tests, "
            f"{figure(d, 'gm_paper_seconds'):.0f} s with the paper's.\n\n" + caption(d, "maneuver.json"))


#: The blocks of the page (and of any page that shows them): name -> the function that makes it.
TABLES = {"gm-experiments": gm_experiments, "manoeuvres": manoeuvres}

#: Figures the page quotes in prose: (result file, the figure's keys in it, how the page prints it).
QUOTES = (
    ("gm.json", ("provenance", "load_average", "before", 0), "load average {:.1f}; commit"),
    ("gm.json", ("provenance", "commit"), "commit {}): one cycle"),
    ("gm.json", ("figures", "ml_cycle_latency_3_classes_240_bearings", "value"), "one cycle **{:.1f} ms**"),
    ("gm.json", ("figures", "ml_class_cycles_per_second", "value"), "({:.0f} class-cycles/s;"),
    ("gm.json", ("figures", "gm_experiment_1331_runs_2_workers", "value"), "the 1331-run experiment **{:.0f} s**"),
)
