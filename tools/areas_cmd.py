"""``tmakit areas list`` and ``tmakit areas show NAME``."""

from __future__ import annotations

import envdata
from tools.report import Report


def register(sub, common) -> None:
    p = sub.add_parser("areas", parents=[common], help="built-in sea areas")
    areas_sub = p.add_subparsers(dest="areas_command", metavar="ACTION", required=True)
    p_list = areas_sub.add_parser("list", parents=[common], help="list the built-in areas")
    p_list.set_defaults(func=run_list)
    p_show = areas_sub.add_parser("show", parents=[common], help="describe an area (name or TOML path)")
    p_show.add_argument("name", metavar="AREA")
    p_show.set_defaults(func=run_show)


def run_list(args) -> Report:
    rows = []
    for name in envdata.builtin_area_names():
        area = envdata.load_area(name)
        rows.append({"name": name, "description": area.description,
                     "default": name == envdata.DEFAULT_AREA})
    width = max(len(r["name"]) for r in rows)
    lines = [f"{r['name']:<{width}}  {'(default) ' if r['default'] else ''}{r['description']}" for r in rows]
    return Report("\n".join(lines), {"areas": rows})


def run_show(args) -> Report:
    area = envdata.load_area(args.name)
    lines = [f"{area.name}: {area.description}", *_water_lines(area),
             f"  bottom: {area.bottom.speed_mps:g} m/s, {area.bottom.density_gcc:g} g/cm^3, "
             f"{area.bottom.attenuation_db_per_wavelength:g} dB/wavelength",
             f"  sea noise: {area.noise.spectrum_level_1khz_db:g} dB re 1 uPa^2/Hz at 1 kHz, "
             f"{area.noise.slope_db_per_octave:g} dB/octave",
             f"  observer depth: {area.observer.depth_m:g} m",
             f"  sonar: beamwidth {area.sonar.beamwidth_deg:g} deg, DI {area.sonar.directivity_index_db:g} dB, "
             f"T {area.sonar.integration_time_s:g} s, threshold Q = {area.sonar.detection_threshold:g}",
             "  bands:"]
    lines += [f"    {b.name}: {b.low_hz:g}-{b.high_hz:g} Hz (centre {b.center_hz:.1f} Hz)" for b in area.bands]
    lines.append("  classes:")
    for c in area.classes:
        level = (f"P0 {c.noise_mean_db:g} +- {c.noise_sd_db:g} dB re 1 uPa" if c.noise_mean_db is not None
                 else "Ross source level")
        lines.append(f"    {c.name}: depth {c.depth_m:g} m, speed {c.speed_mean_mps:g} +- "
                     f"{c.speed_sd_mps:g} m/s, {level}, K error sd {c.k_error_sd_db:g} dB")
    g = area.grid
    deepest = f"{area.water.depth_m:g} m" if area.water.is_flat else "the deepest bottom"
    lines.append(f"  grid: ranges {g.range_step_m:g}-{g.range_max_m:g} m step {g.range_step_m:g} m, "
                 f"depths 0-{deepest} step {g.depth_step_m:g} m")
    p = area.propagation
    lines.append(f"  BELLHOP: {p.mode}, beams {p.beam_type} x {p.n_beams or 'auto'} over "
                 f"{p.angle_min_deg:g}..{p.angle_max_deg:g} deg, absorption {p.absorption}")
    return Report("\n".join(lines), area.to_dict())


def _water_lines(area: envdata.Area) -> list[str]:
    """The water of an area in words: bottom, sound speed and, with [origin], the radials."""
    water = area.water
    if water.is_flat:
        bottom = f"{water.depth_m:g} m deep (flat)"
    else:
        variable = water.bathymetry.variable or "elevation"
        bottom = f"bottom from {water.bathymetry.file.path} ({variable})"
    if water.ssp is not None:
        ssp = water.ssp
        speed = (f"{ssp.kind} profile, {len(ssp.depth_m)} points, "
                 f"{min(ssp.speed_mps):.1f}-{max(ssp.speed_mps):.1f} m/s")
    elif water.ts is not None:
        speed = f"T/S profile, {len(water.ts.depth_m)} points to {water.ts.depth_m[-1]:g} m (TEOS-10)"
    else:
        clim = water.climatology
        files = (clim.file.path if clim.file is not None
                 else f"{clim.temperature_file.path} + {clim.salinity_file.path}")
        speed = f"climatology {files}" + (f", month {clim.month}" if clim.month else "")
    if water.cast is not None:
        speed += f" (cast {water.cast.path})"
    lines = [f"  water: {bottom}, {speed}"]
    if area.origin is not None:
        bearings = area.bearings.bearing_deg
        lines.append(f"  origin: {area.origin.lat_deg:g} N, {area.origin.lon_deg:g} E; "
                     f"{len(bearings)} radials, {', '.join(f'{b:g}' for b in bearings)} deg")
    return lines
