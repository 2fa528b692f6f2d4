"""docs/planning.md: its tables, made from ``docs/results/planning.json`` (``python -m
bench.bench_planning``)."""

from __future__ import annotations

from pathlib import Path

from bench.docfigures.common import caption, load_result, markdown_table

PAGE = "docs/planning.md"
FILE = "planning.json"
LEVELS = ("0.9", "0.5", "0.1")


def _range_cell(e: dict) -> str:
    """A level's range over the radials: the median and its span, or beyond the table."""
    n, past = e["radials"], e["beyond_table"]
    if past == n:
        return "beyond the table" if n == 1 else f"beyond the table on all {n}"
    if e["median_m"] is None:
        given = "" if e["min_m"] is None else (
            f"; {e['min_m'] / 1000:.1f} km on the others" if e["max_m"] - e["min_m"] < 100.0
            else f"; {e['min_m'] / 1000:.1f}-{e['max_m'] / 1000:.1f} km on the others")
        return f"beyond the table on {past} of {n}{given}"
    text = f"{e['median_m'] / 1000:.1f} km"
    if n > 1 and e["min_m"] is not None and e["max_m"] - e["min_m"] >= 100.0:
        text += f" ({e['min_m'] / 1000:.1f}-{e['max_m'] / 1000:.1f})"
    if past:
        text += f"; beyond on {past} of {n}"
    return text


def planning_areas(root: Path) -> str:
    """Per built-in area and class: the P_D 0.9 / 0.5 / 0.1 ranges in any band."""
    d = load_result(root, FILE)
    rows = [("area (tables to)", "class, level, sigma", "P_D 0.9", "P_D 0.5", "P_D 0.1"), ("---",) * 5]
    for area, a in d["areas"].items():
        where = f"{area} ({a['range_max_m'] / 1000:g} km, {a['radials']} radial{'s' if a['radials'] > 1 else ''})"
        for c, info in a["classes"].items():
            cells = [_range_cell(info["ranges"]["any"][level]) for level in LEVELS]
            rows.append((where, f"{c}, {info['level']}, \u03c3 {info['sigma_db']:.1f} dB", *cells))
            where = ""
    return markdown_table(rows) + "\n" + caption(d, FILE)


def planning_reach(root: Path) -> str:
    """Per area, class and band whose P_D still reaches 0.1 at the table's end: how far the axis
    would have to go."""
    d = load_result(root, FILE)
    rows = [("area", "class", "band", "P_D at the last range (largest)", "radials past the end",
             "the axis would have to reach (K's tail)"), ("---",) * 6]
    for area, a in d["areas"].items():
        inside = [f"{r['class']} {r['band']}" for r in a["reach"] if r["inside"]]
        for r in a["reach"]:
            if r["inside"]:
                continue
            rows.append((area, r["class"], r["band"], f"{r['pd_at_table_end']:.2f}",
                         f"{r['bearings_beyond_table']} of {r['bearings']}",
                         f"about {r['range_needed_m'] / 1000:,.0f} km ({r['tail_spreading_db_per_decade']:.1f} dB "
                         "per decade)"))
        if inside:
            rows.append((area, "inside the table", ", ".join(inside), "< 0.1", "0", "-"))
    return markdown_table(rows) + "\n" + caption(d, FILE)


def planning_track(root: Path) -> str:
    """The cumulative P_D along gm-nps at a few times."""
    d = load_result(root, FILE)
    t = d["track"]
    base, look = t["cases"]["tables"], t["cases"]["look_sd_2db"]
    rows = [("time, min", "range, km", "any band (bands independent)", "any band, one offset for all bands",
             "best band alone", "any band, with a 2 dB per-look part"), ("---",) * 6]
    bands = [k for k in base["cum_pd"] if k != "any"]
    for i, ts in enumerate(base["t_s"]):
        best = max(base["cum_pd"][b][i] for b in bands)
        rows.append((f"{ts / 60:g}", f"{base['range_m'][i] / 1000:.1f}", f"{base['cum_pd']['any'][i]:.3f}",
                     f"{base['cum_pd_any_shared'][i]:.3f}", f"{best:.3f}", f"{look['cum_pd']['any'][i]:.3f}"))
    first = base["first_detection"]
    mean, shared = first["any"]["mean_s_given_detected"], first["any_shared"]["mean_s_given_detected"]
    rows.append(("first detection, mean given one", "", f"{mean / 60:.1f} min", f"{shared / 60:.1f} min", "",
                 f"{look['first_detection']['any']['mean_s_given_detected'] / 60:.1f} min"))
    return markdown_table(rows) + "\n" + caption(d, FILE)


def planning_extension(root: Path) -> str:
    """shelf-break from 30 to 45 km: K measured against the 30 km table's tail, and the builds."""
    import numpy as np

    d = load_result(root, FILE)
    e = d["shelf_extension"]
    rows = [("class, band", "K at 45 km, dB", "from the 30 km tail, dB", "SE at 45 km, dB", "P_D at 45 km",
             "axis needed: from 30 km / from 45 km"), ("---",) * 6]
    for c, info in e["classes"].items():
        for ib, band in enumerate(e["bands"]):
            need = [info["range_needed_m"][key][ib] for key in ("30km", "45km")]
            rows.append((f"{c} {band}", f"{np.median(info['k_at_45km_db'][ib]):.1f}",
                         f"{np.median(info['k_at_45km_from_the_30km_tail_db'][ib]):.1f}",
                         f"{np.median(info['se_at_45km_db'][ib]):.1f}", f"{np.min(info['pd_at_45km'][ib]):.3f}",
                         " / ".join("-" if v is None else f"{v / 1000:,.0f} km" for v in need)))
    b = e["build_seconds"]
    rows.append(("build, 4 radials, 2 workers", f"45 km: {b['45km']:.0f} s", f"30 km: {b['30km']:.0f} s",
                 f"{e['build_time_ratio']:.2f}x", "", ""))
    return markdown_table(rows) + "\n" + caption(d, FILE)


def planning_sonar(root: Path) -> str:
    """shelf-break heard by the demo's sonar, in its own sea and in sea state 4: the P_D ranges in
    any band per class, and on how many radials P_D is still 0.1 at the table's end."""
    d = load_result(root, FILE)
    s = d["demo_sonar"]
    rows = [("sea (noise at 1 kHz)", "class", "P_D 0.9", "P_D 0.5", "P_D 0.1"), ("---",) * 5]
    for name, sea in s["seas"].items():
        where = f"{'its own' if name == 'own' else name.replace('_', ' ')} ({sea['noise_1khz_db']:g} dB)"
        for c, ranges in sea["ranges_any"].items():
            cells = ["never heard" if ranges[level]["min_m"] is None and not ranges[level]["beyond_table"]
                     else _range_cell(ranges[level]) for level in LEVELS]
            rows.append((where, c, *cells))
            where = ""
    return f"*{s['label']}; tables of {s['area']}.*\n\n" + markdown_table(rows) + "\n" + caption(d, FILE)


def planning_atlas(root: Path) -> str:
    """The atlas's positions, month by month: the median P_D = 0.5 range of the submarine."""
    d = load_result(root, FILE)
    a = d["atlas"]
    months = a["months"]
    rows = [("position", "band", *(f"month {m}" for m in months)), ("---",) * (2 + len(months))]
    cells: dict = {}
    for r in a["rows"]:
        if r["level"] != 0.5:
            continue
        key = (r["origin"], f"{r['lat_deg']:.3f} N {r['lon_deg']:.3f} E", r["row"])
        past = r["bearings_beyond"]
        text = ("beyond" if r["median_beyond_table"] else f"{r['median_m'] / 1000:.1f} km") + \
            (f" ({past}/{r['bearings']} beyond)" if past and not r["median_beyond_table"] else "")
        cells.setdefault(key, {})[r["month"]] = text
    for (o, where, row), by_month in sorted(cells.items(), key=lambda kv: (kv[0][0], kv[0][2] != "any", kv[0][2])):
        rows.append((f"{o}: {where}", row, *(by_month[m] for m in months)))
    note = (f"*{a['class']} with an array of {a['directivity_index_db']:g} dB, the median over {a['radials']} "
               f"radials of the largest range where P_D >= 0.5; tables to {a['range_max_m'] / 1000:g} km; "
               f"{a['tables']} tables built in {a['build_seconds']:.0f} s on 2 workers.*\n\n")
    return note + markdown_table(rows) + "\n" + caption(d, FILE)


#: The page's prose quotes no figure of its own: the numbers it discusses are the blocks' (each made
#: from docs/results/planning.json); its sentences about them are read against the blocks whenever
#: the file is made again.
QUOTES = ()

#: The blocks of the page: name -> the function that makes it.
TABLES = {"planning-areas": planning_areas, "planning-reach": planning_reach, "planning-track": planning_track,
          "planning-extension": planning_extension, "planning-atlas": planning_atlas, "planning-sonar": planning_sonar}
