"""BELLHOP input for one radial of a range-dependent area: .env with a 'Q' SSP, .bty and .ssp.

The sound speed is a range-dependent 'Q' (quadrilateral) field read from the .ssp file: NZ rows
(the depths of the .env's profile, which must end exactly at the deepest bottom) by one column
per profile range, ranges in km. BELLHOP stops with "ray is outside the box where the soundspeed
is defined" when a ray leaves the columns' ranges, and a ray is traced until |r| reaches the
box's range, behind the source too; so the columns are continued, unchanged, to -box and +box.
The bottom is read from the .bty file (option 'A~', piecewise linear 'L', ranges in km, depths
in m; a run with the water mirrored above the surface, ``RunSpec.mirror_surface``, has the
sound-speed rows mirrored too and its top in an .ati file, the .bty's depths negated); BELLHOP
itself continues it beyond its ends at the end depths. With ``[propagation]
bottom_tolerance_m`` set, the radial's samples (every grid range step, interpolated between the
bathymetry's cells) are thinned to the fewest that hold the polyline within it of every sample
(`thinned_bottom`): BELLHOP shortens a ray's step at each segment of the bottom it crosses, so
on a 50 km radial sampled every 100 m that crossing, more than the ray step, sets a run's cost.
By default (0) every sample is kept. The ray step is the
area's ``[propagation] step_m``, never BELLHOP's automatic one (a tenth of the depth, which is
not converged on deep radials).
"""

from __future__ import annotations

import numpy as np

from acoustics.bellhop.envfile import RunSpec, env_lines, fmt_number, mirror_at_surface
from envdata.area import Area


def thinned_bottom(range_m, depth_m, tolerance_m: float) -> np.ndarray:
    """Indices of the samples a piecewise-linear bottom keeps (the ends always) so that it passes
    within ``tolerance_m`` in depth of every sample (Douglas-Peucker on the vertical distance);
    every sample where ``tolerance_m`` is 0 (collinear ones too)."""
    r = np.asarray(range_m, dtype=float)
    z = np.asarray(depth_m, dtype=float)
    if tolerance_m <= 0.0:
        return np.arange(r.size)
    keep = np.zeros(r.size, dtype=bool)
    keep[[0, -1]] = True
    spans = [(0, r.size - 1)] if r.size > 2 else []
    while spans:
        i, j = spans.pop()
        inner = slice(i + 1, j)
        chord = z[i] + (z[j] - z[i]) * (r[inner] - r[i]) / (r[j] - r[i])
        miss = np.abs(z[inner] - chord)
        k = int(np.argmax(miss))
        if miss[k] > tolerance_m:
            k += i + 1
            keep[k] = True
            spans.extend(s for s in ((i, k), (k, j)) if s[1] - s[0] > 1)
    return np.flatnonzero(keep)


def radial_files(area: Area, radial, spec: RunSpec, *, step_m: float,
                 box_range_m: float) -> dict[str, str]:
    """The texts of ``{"env": ..., "bty": ..., "ssp": ...}`` for one radial.

    Parameters
    ----------
    area : Area
        The area (bottom half-space, SSP interpolation and volume absorption settings).
    radial : envdata.radials.Radial
        Bottom depth along the radial and its sound-speed section.
    spec : RunSpec
        Frequency, source and receiver depths, receiver ranges and the beam fan.
    step_m : float
        Ray step, m (> 0).
    box_range_m : float
        Rays stop at |r| >= this, m; the sound-speed field covers [-box, +box].
    """
    z = np.asarray(radial.ssp_depth_m, dtype=float)
    c = np.asarray(radial.speed_mps, dtype=float)
    r = np.asarray(radial.ssp_range_m, dtype=float)
    # BELLHOP asks for the sound speed at the end of the step that leaves the box, so the
    # columns reach a few steps beyond it
    reach_m = box_range_m + 10.0 * step_m + 1000.0
    if r[0] > -reach_m:  # continue the first column behind the origin past the box
        r, c = np.concatenate([[-reach_m], r]), np.concatenate([c[:, :1], c], axis=1)
    if r[-1] < reach_m:
        r, c = np.concatenate([r, [reach_m]]), np.concatenate([c, c[:, -1:]], axis=1)
    at_origin = c[:, int(np.argmin(np.abs(r)))]  # the .env's own profile: the column at the origin
    env = env_lines(spec, area.bottom, depth_m=float(z[-1]), ssp_depth_m=z, ssp_speed_mps=at_origin, interpolation="Q",
                    bottom_option="A~", step_m=step_m, box_range_km=box_range_m / 1000.0)

    kept = thinned_bottom(radial.range_m, radial.bottom_depth_m, area.propagation.bottom_tolerance_m)
    bty_r_km = np.asarray(radial.range_m, dtype=float)[kept] / 1000.0
    bty_z_m = np.asarray(radial.bottom_depth_m, dtype=float)[kept]
    bty = "\n".join(["'L'", str(bty_r_km.size)] +
                    [f"{fmt_number(rk)} {fmt_number(zb)}" for rk, zb in zip(bty_r_km, bty_z_m)])
    if spec.mirror_surface:  # the water mirrored above the surface (envfile.mirrored_lines)
        c = mirror_at_surface(z, c)[1]
    ssp_rows = [" ".join(f"{v:.3f}" for v in row) for row in c]
    ssp = "\n".join([str(r.size), " ".join(fmt_number(v) for v in r / 1000.0)] + ssp_rows)
    files = {"env": env, "bty": bty + "\n", "ssp": ssp + "\n"}
    if spec.mirror_surface:  # the top: the bottom's mirror image
        files["ati"] = "\n".join(["'L'", str(bty_r_km.size)] + [f"{fmt_number(rk)} {fmt_number(-zb)}"
                                                                for rk, zb in zip(bty_r_km, bty_z_m)]) + "\n"
    return files
