"""Writing BELLHOP environment (.env) files from an area and a run specification."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from envdata.area import Absorption, Area, TlMode
from envdata.bottom import Bottom


@dataclass(frozen=True, slots=True, kw_only=True)
class RunSpec:
    """One BELLHOP run: one frequency, one or more source depths, a rectilinear receiver grid."""

    title: str
    freq_hz: float
    source_depth_m: tuple[float, ...]
    receiver_depth_m: tuple[float, ...]
    range_m: tuple[float, ...]
    mode: TlMode = TlMode.INCOHERENT
    beam_type: str = "G"
    n_beams: int = 0
    angle_min_deg: float = -80.0
    angle_max_deg: float = 80.0
    absorption: Absorption = Absorption.THORP
    #: the source's beam pattern: (angle deg, intensity dB) pairs, angles increasing; BELLHOP
    #: reads it from a .sbp file beside the .env (run type '*') and interpolates the amplitude
    source_pattern: tuple[tuple[float, float], ...] | None = None
    #: an arrivals run (run type 'a': every arrival's amplitude, delay and angles, binary .arr)
    #: in place of the TL field
    arrivals: bool = False
    #: the water mirrored above the sea surface (``mirrored_lines``): no surface, the bottom's
    #: mirror image as the top, a receiver at each depth's mirror -z too (the surface image of a
    #: target that is the receiver, ``acoustics.builder.surfaceimage``)
    mirror_surface: bool = False

    def receiver_rows_m(self) -> tuple[float, ...]:
        """The depths BELLHOP receives at: ``receiver_depth_m``, and with ``mirror_surface`` the
        mirror -z of each z > 0 before them (increasing)."""
        if not self.mirror_surface:
            return self.receiver_depth_m
        return tuple(float(z) for z in mirror_at_surface(self.receiver_depth_m)[0])

    @property
    def run_type(self) -> str:
        """BELLHOP's run-type string: mode (or 'a'), beam type, '*' with a source pattern."""
        letter = "a" if self.arrivals else self.mode.bellhop_letter
        return f"{letter}{self.beam_type}{'*' if self.source_pattern is not None else ''}"

    def side_files(self) -> dict[str, str]:
        """Files BELLHOP reads beside the .env for this run: the .sbp of a source pattern."""
        return {"sbp": sbp_text(self.source_pattern)} if self.source_pattern is not None else {}


def mirror_at_surface(depth_m, *rows):
    """Depths (increasing) and what is given at them (``rows``, indexed by depth along their first
    axis) mirrored above the surface: the mirror -z of each z > 0, deepest first, then the depths
    as they are; each row's values in the same order."""
    z = np.asarray(depth_m, dtype=float)
    above = np.flatnonzero(z > 0.0)[::-1]
    return (np.concatenate([-z[above], z]),
            *(np.concatenate([np.asarray(r)[above], np.asarray(r)]) for r in rows))


def sbp_text(pattern) -> str:
    """A source beam-pattern (.sbp) file: the count, then one 'angle dB' line per point."""
    lines = [str(len(pattern))] + [f"{a:.6f} {db:.4f}" for a, db in pattern]
    return "\n".join(lines) + "\n"


def fmt_number(value: float) -> str:
    """A number as BELLHOP reads it: fixed point, at most six decimals, no trailing zeros."""
    return f"{value:.6f}".rstrip("0").rstrip(".") if value != 0 else "0.0"


def fmt_list(values, per_line: int = 10) -> str:
    """Numbers ten to a line, closed by BELLHOP's list terminator '/'."""
    items = [fmt_number(float(v)) for v in values]
    lines = [" ".join(items[i:i + per_line]) for i in range(0, len(items), per_line)]
    return "\n".join(lines) + " /"


def env_lines(spec: RunSpec, bottom: Bottom, *, depth_m: float, ssp_depth_m, ssp_speed_mps,
              interpolation: str, bottom_option: str, step_m: float, box_range_km: float) -> str:
    """The .env text of one run: ``spec``'s frequency, sources, receivers and beams over the
    profile given, a half-space ``bottom`` at ``depth_m`` (the deepest bottom), and the ray box.

    ``interpolation`` is BELLHOP's SSP letter ('C', 'S', 'N', 'P' or 'Q' for a range-dependent
    .ssp beside the .env), ``bottom_option`` 'A' (flat) or 'A~' (a .bty beside the .env).
    """
    depth_max = float(depth_m)
    # SSP options: interpolation, vacuum surface, attenuation in dB/wavelength, volume attenuation
    volume = "T" if spec.absorption is Absorption.THORP else " "
    half_space = (f"{fmt_number(depth_max)} {fmt_number(bottom.speed_mps)} {fmt_number(bottom.shear_speed_mps)} "
                  f"{fmt_number(bottom.density_gcc)} {fmt_number(bottom.attenuation_db_per_wavelength)} 0.0 /")
    if spec.mirror_surface:
        lines = mirrored_lines(spec, half_space, depth_max=depth_max, ssp_depth_m=ssp_depth_m,
                               ssp_speed_mps=ssp_speed_mps, interpolation=interpolation, volume=volume,
                               altimetry="~" in bottom_option)
    else:
        lines = [f"'{spec.title[:70]}'", fmt_number(spec.freq_hz), "1", f"'{interpolation}VW{volume}'",
                 f"0 0.0 {fmt_number(depth_max)}"]
        lines += [f"{fmt_number(z)} {fmt_number(c)} /" for z, c in zip(ssp_depth_m, ssp_speed_mps)]
    lines += [f"'{bottom_option}' 0.0", half_space]
    lines += [str(len(spec.source_depth_m)), fmt_list(spec.source_depth_m)]
    receivers = spec.receiver_rows_m()
    lines += [str(len(receivers)), fmt_list(receivers)]
    range_km = np.asarray(spec.range_m, dtype=float) / 1000.0  # BELLHOP reads ranges in km
    lines += [str(len(range_km)), fmt_list(range_km)]
    lines += [f"'{spec.run_type}'", str(spec.n_beams),
              f"{fmt_number(spec.angle_min_deg)} {fmt_number(spec.angle_max_deg)} /"]
    box_depth_m = depth_max * 1.01 + 1.0  # rays leaving this box stop; the bottom reflects first
    lines.append(f"{fmt_number(step_m)} {fmt_number(box_depth_m)} {fmt_number(box_range_km)}")
    return "\n".join(lines) + "\n"


def mirrored_lines(spec: RunSpec, half_space: str, *, depth_max: float, ssp_depth_m, ssp_speed_mps,
                   interpolation: str, volume: str, altimetry: bool) -> list[str]:
    """The .env's head (title to the last SSP point) with the water mirrored above the surface.

    The surface is gone: the water runs from -depth_max to depth_max, its profile mirrored at 0,
    and its top is the bottom's half-space, at the mirror image of the bottom (a flat top at
    -depth_max, or with ``altimetry`` the .ati beside the .env that
    ``acoustics.bellhop.radialfiles.radial_files`` writes). A ray that reflects at the sea surface
    runs on through the mirror instead, so a receiver at -z hears the surface-reflected paths to z
    exactly (the method of images), and a hat beam is never cut short at the surface. Each SSP
    point gives its density and attenuation (1 g/cm3, none): BELLHOP otherwise takes them from the
    top half-space read before it. A spline or PCHIP profile ('S', 'P') is fitted through the
    mirrored points, so within its first interval below 0 it bends where the sea's own ended.
    """
    if ssp_depth_m[0] != 0.0:
        raise ValueError(f"a mirrored profile starts at the surface, this one at {ssp_depth_m[0]} m")
    zs, cs = mirror_at_surface(ssp_depth_m, np.asarray(ssp_speed_mps, dtype=float))
    lines = [f"'{spec.title[:70]}'", fmt_number(spec.freq_hz), "1",
             f"'{interpolation}AW{volume}{'*' if altimetry else ''}'", half_space, f"0 0.0 {fmt_number(depth_max)}"]
    return lines + [f"{fmt_number(zi)} {fmt_number(ci)} 0.0 1.0 0.0 0.0 /" for zi, ci in zip(zs, cs)]


def env_text(area: Area, spec: RunSpec) -> str:
    """The .env text for ``spec`` in ``area`` (flat bottom, range-independent profile)."""
    ssp = area.water.ssp
    box_range_km = float(np.max(spec.range_m)) / 1000.0 * 1.01 + 0.01
    # ray step: the area's [propagation] step_m, else 0 (BELLHOP's own: a tenth of the depth)
    step_m = area.propagation.step_m if area.propagation.step_m is not None else 0.0
    return env_lines(spec, area.bottom, depth_m=area.water.depth_m, ssp_depth_m=ssp.depth_m,
                     ssp_speed_mps=ssp.speed_mps, interpolation=ssp.interpolation, bottom_option="A",
                     step_m=step_m, box_range_km=box_range_km)
