"""docs/models.md: the sea surface's checks and cost, the grid check, BELLHOP against RAM (the areas and
the crossover), the models' build speed."""

from __future__ import annotations

from pathlib import Path

from bench.docfigures.common import caption, figure, load_result, markdown_table

PAGE = "docs/models.md"


def _pm(s: dict, key: str = "p90_db") -> str:
    return f"{s['median_db']:.2f} / {s[key]:.2f} / {s['mean_db']:+.2f}"


def surface(root: Path) -> str:
    d = load_result(root, "surface.json")
    c = d["cases"]
    rows = [("case", "semicoherent (the default): median / p90 / mean, dB", "incoherent beams",
             "bound (median / mean)"), ("---", "---", "---", "---")]
    pairs = [
        ("image-source solution, flat grid, 6 m source, 100-300 Hz", "image flat 100-300 Hz", "0.1 median"),
        ("Munk channel, flat grid TL beyond 5 km, 6 m, 100 Hz tone", "munk flat TL beyond 5 km, 100 Hz tone",
         "1.5 / 1"),
        ("the same, 89-112 Hz", "munk flat TL beyond 5 km, 89-112 Hz", ""),
        ("Munk, table from the 100 m observer, 6 m target, beyond 30 km, 89-112 Hz",
         "munk from the observer, 6 m to 100 m beyond 30 km, 89-112 Hz", "3.5 / 1.5"),
        ("the same, 100 Hz tone", "munk from the observer, 6 m to 100 m beyond 30 km, 100 Hz tone", ""),
        ("200 m shelf, flat grid, 5 m source, 250 Hz, 2-20 km", "shelf 5 m 250 Hz, 2-20 km", "1 / (p90 2.5)"),
    ]
    for label, key, bound in pairs:
        rows.append((label, _pm(c[f"{key}, semicoherent"]), _pm(c[f"{key}, incoherent"]), bound))
    k = c["image from the observer 100-300 Hz, semicoherent"]["k"]
    rows.append(("image-source solution, table from the 100 m observer, K of the 6 m target", _pm(k), "", "0.1 median"))
    for mode in ("semicoherent", "incoherent"):
        rec = c[f"reciprocity ocean-deep K to 40 km, {mode}"]
        worst = max(rec.values(), key=lambda x: x["median_db"])
        c[f"_rec_{mode}"] = worst
    rows.append(("ocean-deep, K of SW and TV from the observer against the targets' own runs (worst class and band)",
                 _pm(c["_rec_semicoherent"]), _pm(c["_rec_incoherent"]), "0.5 median"))
    return markdown_table(rows) + "\n" + caption(d, "surface.json")


def surface_cost(root: Path) -> str:
    d = load_result(root, "surface-cost.json")
    rows = [("build (2 workers)", "incoherent", "semicoherent (the default)", "wall ratio", "BELLHOP ratio"),
            ("---", "---", "---", "---", "---")]
    for name, b in d["builds"].items():
        rows.append((name, f"{b['wall_incoherent_s']:.1f} s ({b['runs_incoherent']} runs)",
                     f"{b['wall_semicoherent_s']:.1f} s ({b['runs_semicoherent']} runs)",
                     f"{b['wall_ratio']:.2f}x", f"{b['bellhop_ratio']:.2f}x"))
    return markdown_table(rows) + "\n" + caption(d, "surface-cost.json")


def grids_check(root: Path) -> str:
    d = load_result(root, "grids-check.json")
    rows = [("area", "doubled", "K moves: median (worst class and band), dB", "converged"),
            ("---", "---", "---", "---")]
    for area, result in d["areas"].items():
        for v in result["variants"]:
            rows.append((area, v["change"], f"{v['median_db']:.2f} ({v['worst_db']:.2f} {v['worst']})",
                         "yes" if v["converged"] else "no"))
    return markdown_table(rows) + "\n" + caption(d, "grids-check.json")


def _whole(case: dict) -> dict:
    """(class, band) -> the comparison's row over all bearings of a models-study case."""
    return {(r["class"], r["band"]): r for r in case["rows"] if r["bearing_deg"] is None}


def _per_class(values: list[str], classes: list[str]) -> str:
    """One value when every class has it, else each with its class."""
    if len(set(values)) == 1:
        return values[0]
    return ", ".join(f"{v} ({c})" for v, c in zip(values, classes))


def _cut(case: dict) -> str:
    bearings = sorted({r["bearing_deg"] for r in case["rows"] if r["bearing_deg"] is not None})
    base = case["area"].split("-fb")[0].removesuffix("-crossover")
    bands = "/".join(b[0] for b in case["bands"])
    where = (f", radial{'s' if len(bearings) > 1 else ''} {'/'.join(f'{b:g}' for b in bearings)} deg"
             if bearings else "")
    return f"{base} {bands}{where} to {case['range_max_m'] / 1000:g} km"


def models_areas(root: Path) -> str:
    d = load_result(root, "models-areas.json")
    rows = [("area, band, cut", "\\|dTL\\| median / p90", "\\|dK\\| median / p90, NPS (200 m)", "SW (6 m)",
             "TV (8 m)", "rms dK, NPS / SW / TV", "RAM runs, run time", "BELLHOP runs, run time"),
            ("---",) * 8]
    for case in d["cases"]:
        whole = _whole(case)
        classes = list(dict.fromkeys(c for c, _ in whole))
        band = case["bands"][0][0]
        tl = [f"{whole[(c, band)]['tl_median_db']:.2f} / {whole[(c, band)]['tl_p90_db']:.2f} dB" for c in classes]
        k = [f"{whole[(c, band)]['k_median_db']:.2f} / {whole[(c, band)]['k_p90_db']:.2f} dB" for c in classes]
        rms = " / ".join(f"{whole[(c, band)]['k_rms_db']:.2f}" for c in classes) + " dB"
        ram, bh = case["ram"], case["bellhop"]
        rows.append((_cut(case), _per_class(tl, classes), *k, rms,
                     f"{ram['runs']}, {ram['run_seconds']:.0f} s ({ram['wall_s']:.0f} s wall)",
                     f"{bh['runs']}, {_secs(bh['run_seconds'])} s ({case.get('bellhop_mode', 'incoherent')}, "
                     f"{case.get('bellhop_beams', '?')} beams)"))
    return markdown_table(rows) + "\n" + caption(d, "models-areas.json")


def _secs(x: float) -> str:
    return f"{x:.2g}" if x < 10.0 else f"{x:.0f}"


def ram_crossover(root: Path) -> str:
    d = load_result(root, "ram-crossover.json")
    rows = [("band", "\\|dTL\\| median / p90", "\\|dK\\| median, NPS / SW / TV", "rms dK, NPS / SW / TV"),
            ("---",) * 4]
    for case in d["cases"]:
        whole = _whole(case)
        classes = list(dict.fromkeys(c for c, _ in whole))
        for name, low, high in case["bands"]:
            tl = [f"{whole[(c, name)]['tl_median_db']:.2f} / {whole[(c, name)]['tl_p90_db']:.2f} dB" for c in classes]
            rows.append((f"{low:.0f}-{high:.0f} Hz", _per_class(tl, classes),
                         " / ".join(f"{whole[(c, name)]['k_median_db']:.2f}" for c in classes) + " dB",
                         " / ".join(f"{whole[(c, name)]['k_rms_db']:.2f}" for c in classes) + " dB"))
    return markdown_table(rows) + "\n" + caption(d, "ram-crossover.json")


def models_bench(root: Path) -> str:
    d = load_result(root, "models.json")
    runs = figure(d, "ram_runs")
    rows = [("figure", "value"), ("---", "---"),
            (f"RAM runs ({runs // 21} radials x 21 frequencies)", f"{runs}"),
            ("BELLHOP build, 2 workers",
             f"{figure(d, 'bellhop_w2_wall'):.2f} s, peak {figure(d, 'bellhop_w2_peak_rss'):.0f} MiB"),
            ("RAM build, 1 worker",
             f"{figure(d, 'ram_w1_wall'):.1f} s ({figure(d, 'ram_run_seconds_sum_w1'):.1f} s of runs), "
             f"peak {figure(d, 'ram_w1_peak_rss'):.0f} MiB"),
            ("RAM build, 2 workers", f"{figure(d, 'ram_w2_wall'):.1f} s, peak {figure(d, 'ram_w2_peak_rss'):.0f} MiB"),
            ("RAM on 2 workers over BELLHOP on 2 workers", f"{figure(d, 'ram_w2_over_bellhop_w2'):.2g}x"),
            ("RAM, 2 workers against 1", f"{figure(d, 'ram_speedup_2_vs_1'):.2f}x (target >= 1.8x)")]
    return markdown_table(rows) + "\n" + caption(d, "models.json")


def _wall_ratios(d: dict) -> list[float]:
    """RAM's wall time over BELLHOP's, each case of a models-study file."""
    return [c["ram"]["wall_s"] / c["bellhop"]["wall_s"] for c in d["cases"]]


def _least_wall_ratio(d: dict) -> float:
    return min(_wall_ratios(d))


def _greatest_wall_ratio(d: dict) -> float:
    return max(_wall_ratios(d))


def _shelf_wall_over_bellhop(d: dict) -> float:
    """The shelf-break grid build's wall time over its BELLHOP runs' time (build-profile.json)."""
    b = d["profiles"]["now"]["builds"]["shelf-break grid"]
    return b["wall_s"] / (b["seconds"]["bellhop field runs"] + b["seconds"]["bellhop arrivals runs"])


def build_profile(root: Path) -> str:
    """Where each build's time goes, now and before the change, seconds summed over threads."""
    d = load_result(root, "build-profile.json")
    sides = [s for s in ("now", "before") if s in d["profiles"]]
    builds = list(d["profiles"]["now"]["builds"])
    head = ["seconds (1 worker; medians of %d)" % d["repeats"]]
    for b in builds:
        head += [f"{b}, {s}" if len(sides) > 1 else b for s in sides]
    rows = [tuple(head), ("---",) * len(head)]

    def cell(side, build, key):
        return d["profiles"][side]["builds"][build][key]

    rows.append(("BELLHOP runs (field + arrivals)", *(
        f"{cell(s, b, 'bellhop_runs')['bellhop field runs']} + {cell(s, b, 'bellhop_runs')['bellhop arrivals runs']}"
        for b in builds for s in sides)))
    for cat in d["profiles"]["now"]["builds"][builds[0]]["seconds"]:
        rows.append((cat, *(f"{cell(s, b, 'seconds')[cat]:.2f}" for b in builds for s in sides)))
    rows.append(("**the build's wall time**", *(f"**{cell(s, b, 'wall_s'):.1f}**" for b in builds for s in sides)))
    rows.append(("the command's process, start-up included", *(f"{cell(s, b, 'process_s'):.1f}"
                                                              for b in builds for s in sides)))
    text = markdown_table(rows)
    same = d.get("now_against_before")
    if same:
        text += (f"\nThe shelf-break grids now and before: largest |dTL| {same['tl_db max |difference|']:.3g} dB, "
                 f"|dK| {same['k_db max |difference|']:.3g} dB where both are finite; the same NaN cells: "
                 f"{'yes' if same['tl_db same NaN cells'] and same['k_db same NaN cells'] else 'no'}.\n")
    return text + "\n" + caption(d, "build-profile.json")


def surface_candidates(root: Path) -> str:
    d = load_result(root, "surface-candidates.json")
    rows = [("tables from the observer (shelf-break, 12 radials)", "runs", "BELLHOP CPU", "of before",
             "K moved: median / p90, dB", "TL moved: median / p90, dB",
             "over the incoherent build (same runs / before)"), ("---",) * 7]
    for label, c in d["candidates"].items():
        k = c.get("k_moved")
        tl = c.get("tl_moved")
        rows.append((label, f"{c['runs']}", f"{c['bellhop_cpu_s']:.1f} s", f"{c['over_before']:.2f}",
                     f"{k['median_db']:.3f} / {k['p90_db']:.3f}" if k else "",
                     f"{tl['median_db']:.3f} / {tl['p90_db']:.3f}" if tl else "",
                     f"{c['over_incoherent_same_runs']:.2f}x / {c['over_incoherent_before']:.2f}x"
                     if "over_incoherent_same_runs" in c else ""))
    text = markdown_table(rows)
    ref = d.get("reference_check_db") or {}
    if ref:
        text += ("\nK of ocean-deep's ships from the observer against their own runs (the check in `make test`, "
                 f"worst class and band median, bound {d['reference_bound_db']:g} dB): "
                 + ", ".join(f"{v:.2f} dB with {k} arrivals beams" for k, v in ref.items()) + ".\n")
    return text + "\n" + caption(d, "surface-candidates.json")


def engine(root: Path) -> str:
    d = load_result(root, "engine.json")
    rows = [("runs (shelf-break, bearings " + ", ".join(f"{b:g}" for b in d["bearings_deg"]) + ")",
             "bellhop.exe: wall / CPU", "pelagic: wall / CPU", "pelagic over bellhop.exe, CPU"), ("---",) * 4]
    for kind, r in d["runs"].items():
        rows.append((f"{r['runs']} {kind} runs", f"{r['bellhop_exe_wall_s']:.1f} / {r['bellhop_exe_cpu_s']:.1f} s",
                     f"{r['pelagic_wall_s']:.1f} / {r['pelagic_cpu_s']:.1f} s",
                     f"{r['pelagic_over_bellhop_exe_cpu']:.2f}x"))
    version = d["provenance"]["versions"].get("pelagic", "?")
    text = markdown_table(rows) + "\n"
    text += "; ".join(f"{name}: \\|dTL\\| median {s['median_db']:.2f} dB, p90 {s['p90_db']:.2f} dB"
                      for name, s in d["accuracy"].items()) + f" (pelagic {version}).\n"
    return text + "\n" + caption(d, "engine.json")


def bottom(root: Path) -> str:
    d = load_result(root, "bottom.json")
    rows = [("shelf-break tables (12 radials)", "BELLHOP CPU", "of every sample's", "K moved: median / p90, dB",
             "ships' K against their own runs: worst median, dB", "the same: mean per class and band, dB"),
            ("---",) * 6]
    for label, c in d["shelf_break"].items():
        k = c.get("k_moved")
        vs = c["k_against_targets_own_runs"]
        rows.append((label, f"{c['bellhop_cpu_s']:.1f} s", f"{c['over_every_sample']:.2f}",
                     f"{k['median_db']:.2f} / {k['p90_db']:.2f}" if k else "",
                     f"{c['k_against_targets_worst_median_db']:.2f}",
                     " ".join(f"{v['mean_db']:+.1f}" for v in vs.values())))
    text = markdown_table(rows) + "\n"
    rows = [("36 radials to 50 km (one atlas table)", "BELLHOP CPU per table", "of every sample's",
             "western-Med atlas, CPU h of BELLHOP"), ("---",) * 4]
    for label, c in d["wide_36_radials"].items():
        rows.append((label, f"{c['bellhop_cpu_s_per_table']:.1f} s", f"{c['over_every_sample']:.2f}",
                     f"{c['western_med_bellhop_cpu_hours']:,}"))
    text += markdown_table(rows) + "\n"
    rows = [(f"shelf study, shelf-tv, levels from the tables, {d['shelf_study_runs']} runs", "ML: RMSE after 5 min",
             "PF: RMSE after 5 min", "PF: 90 % range interval covers"), ("---",) * 4]
    for label, c in d["shelf_study"].items():
        e, cov = c["mean_rmse_after_5min_m"], c["range_coverage_90"]
        rows.append((f"tables of {label}", f"{e['ml_bearing'] / 1000:.2f} km", f"{e['rpf_bearing'] / 1000:.2f} km",
                     f"{100 * cov['rpf_bearing']:.0f} %"))
    text += markdown_table(rows)
    return text + "\n" + caption(d, "bottom.json")


def image_mirror(root: Path) -> str:
    d = load_result(root, "image-mirror.json")
    finest = d["finest_beams"]
    rows = [("surface's arrivals run (shelf-break, 12 radials)", "BELLHOP CPU", "of the first row's",
             f"against its own {finest} beams over 1 km: median / p90 / mean, dB"), ("---",) * 4]
    for label, v in d["variants"].items():
        c = v.get("against_finest")
        near = f"{c['km_median_db']:.2f} / {c['km_p90_db']:.2f} / {c['km_mean_db']:+.2f}" if c else "(the finest)"
        rows.append((label, f"{v['bellhop_cpu_s']:.1f} s", f"{v['of_before']:.2f}", near))
    text = markdown_table(rows) + "\n"

    def worst(by_case):
        medians = [s["median_db"] for s in by_case.values()]
        means = [s["mean_db"] for s in by_case.values()]
        return f"{max(medians):.2f}", f"{min(means):+.2f} to {max(means):+.2f}"

    rows = [("ships' K (SW 6 m, TV 8 m; 3 bands)",
             "shelf-break, against BELLHOP from the ship along each true path: worst median / means, dB",
             "ocean-deep, against the ships' own runs: worst median (bound 0.5) / means, dB"), ("---",) * 3]
    for label in d["truth"]:
        t, r = worst(d["truth"][label]), worst(d["reciprocity"][label])
        rows.append((label, f"{t[0]} / {t[1]}", f"{r[0]} / {r[1]}"))
    first = next(iter(next(iter(d["truth"].values())).values()))
    n = first.get("cells", first.get("n"))  # the file made at 50757f5 names the count n
    text += markdown_table(rows)
    text += (f"\nTruth targets: every {d['truth_targets']['radial_step']}rd radial, 2 to 30 km every 1 km where the "
             f"ship has water ({n} per class); means are table minus reference (positive: the table louder).\n")
    return text + "\n" + caption(d, "image-mirror.json")


def surface_price(root: Path) -> str:
    d = load_result(root, "surface-price.json")
    finest = d["finest_beams"]
    rows = [("surface's arrivals run (shelf-break, 12 radials)", "field and arrivals runs over the field runs",
             f"against the mirrored run with {finest} beams over 1 km: median / p90 / mean, dB",
             "ships' K against BELLHOP from the ship: worst median / means, dB"), ("---",) * 4]
    for label, v in d["variants"].items():
        c = v.get("against_finest")
        near = f"{c['km_median_db']:.2f} / {c['km_p90_db']:.2f} / {c['km_mean_db']:+.2f}" if c else "(the finest)"
        lo, hi = v["truth_mean_range_db"]
        truth = f"{v['truth_worst_median_db']:.2f} / {lo:+.2f} to {hi:+.2f}"
        rows.append((label + (" (the default)" if label == f"mirrored, {d['default_beams']}" else ""),
                     f"{v['pair_over_field']:.2f}x", near, truth))
    text = markdown_table(rows)
    text += (f"\nBELLHOP CPU of the processes, medians of the repeats; the field runs took {d['field_cpu_s']:.1f} s. "
             f"Truth targets as above (every {d['truth_targets']['radial_step']}rd radial, 2 to 30 km).\n")
    return text + "\n" + caption(d, "surface-price.json")


#: The blocks of the page (and of any page that shows them): name -> the function that makes it.
TABLES = {"surface": surface, "surface-cost": surface_cost, "grids-check": grids_check, "models-areas": models_areas,
          "ram-crossover": ram_crossover, "models-bench": models_bench, "build-profile": build_profile,
          "surface-candidates": surface_candidates, "image-mirror": image_mirror, "surface-price": surface_price,
          "engine": engine,
          "bottom": bottom}

#: Figures the page quotes in prose: (result file, the figure's keys in it, how the page prints it).
QUOTES = (
    ("build-profile.json", (_shelf_wall_over_bellhop,), "the build's wall time is {:.2f}x BELLHOP's"),
    ("build-profile.json", ("profiles", "now", "startup_s"), "(its imports) to {:.1f} s more"),
    ("models.json", ("figures", "ram_w2_over_bellhop_w2", "value"), "costs {:.2g} times BELLHOP's build"),
    ("models-areas.json", (_least_wall_ratio,), "and {:.0f} to"),
    ("models-areas.json", (_greatest_wall_ratio,), "to {:.0f} times its wall time"),
    ("ram-crossover.json", (_least_wall_ratio,), "(the crossover's {:.0f}x;"),
    ("ram-crossover.json", ("cases", 0, "ram", "runs"), "the {:d} RAM runs took"),
    ("ram-crossover.json", ("cases", 0, "ram", "run_seconds"), "took {:.0f} s of run time"),
    ("ram-crossover.json", ("cases", 0, "ram", "wall_s"), "({:.0f} s wall on 2 workers)"),
    ("ram-crossover.json", ("cases", 0, "bellhop", "runs"), "the {:d} BELLHOP runs"),
    ("ram-crossover.json", ("cases", 0, "bellhop", "run_seconds"), "BELLHOP runs {:.1f} s"),
    ("models.json", ("figures", "ram_speedup_2_vs_1", "value"), "2 workers gave {:.2f}x"),
    ("models.json", ("figures", "bellhop_w2_wall", "value"), "BELLHOP's build is {:.1f} s"),
    ("models.json", ("figures", "ram_w2_over_bellhop_w2", "value"), "is {:.1f} times BELLHOP's build"),
    ("models.json", ("provenance", "load_average", "before", 0), "the load average was {:.1f} at the"),
    ("models.json", ("provenance", "load_average", "after", 0), "and {:.1f} at the end"),
    ("ram-checks.json", ("ram15", "mean_abs_db"), "mean {:.4f} dB,"),
    ("ram-checks.json", ("ram15", "max_abs_db"), "max {:.3f} dB |"),
    ("ram-checks.json", ("ram15", "mean_abs_db"), "| {:.4f} /"),
    ("ram-checks.json", ("ram15", "max_abs_db"), "/ {:.3f} dB |"),
    *(("ram-checks.json", ("pekeris", "by_freq_hz", f, "default", key), fmt) for f, key, fmt in (
        ("100", "median_db", "| {:.2f} /"), ("100", "p90_db", "/ {:.2f} dB,"), ("250", "median_db", ", {:.2f} /"),
        ("250", "p90_db", "/ {:.2f} dB |"), ("100", "median_db", "median {:.2f} /"),
        ("250", "median_db", "/ {:.2f} dB, p90"),
        ("100", "p90_db", "p90 {:.2f} /"), ("250", "p90_db", "/ {:.2f} dB, signed"),
        ("100", "signed_median_db", "signed {:+.2f} /"), ("250", "signed_median_db", "/ {:+.2f} dB |"))),
    *(("ram-checks.json", ("pekeris", "by_freq_hz", f, "lambda_over_20", key), fmt) for f, key, fmt in (
        ("100", "median_db", "(median {:.2f} /"), ("250", "median_db", "/ {:.2f} dB, signed"),
        ("100", "signed_median_db", "signed {:+.2f} /"), ("250", "signed_median_db", "/ {:+.2f} dB), so"))),
)
