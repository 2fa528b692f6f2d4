"""BELLHOP3D input for one Nx2D run over an area's radials: .env, a 3D .bty ('R') and an 'H' .ssp.

Formats (BELLHOP3D's ReadEnvironment, ReadBTY3D and its hexahedral SSP reader):

- .env: BELLHOP's blocks with the SSP option 'H' (the speeds come from the .ssp; the .env's own
  profile, at exactly the .ssp's depths, supplies the volume attenuation, which BELLHOP3D
  interpolates with the .ssp's depth index), the bottom 'A~' (read from the .bty), source x and
  y in km, source depths, receiver depths (m), ranges (km), receiver bearings (deg,
  counter-clockwise from +x = east, increasing), the run type with '2' (Nx2D) in sixth place,
  the elevation fan, the bearing fan (Nx2D replaces it with the receiver bearings), and
  ``step (m), box x (km), box y (km), box z (m)``.
- .bty: ``'R'``, Nx, x (km), Ny, y (km), then Ny rows of Nx depths (m).
- .ssp: Nx, x (km), Ny, y (km), Nz, z (m), then for each depth Ny rows of Nx speeds (m/s).

A ray stops when |x| or |y| reaches the box, or when it leaves the bathymetry grid: a .bty
smaller than the box silently stops rays early (the field beyond is empty, 600 dB), and an .ssp
smaller than the box is fatal ("ray is outside the box where the soundspeed is defined"), also
for the end of the step that crosses the box. So both grids must reach `coverage_m` of the
box: ``nx2d_files`` refuses a `BoxEnvironment` that does not.

tmakit's bearings are clockwise from true north; BELLHOP3D's are counter-clockwise from east:
``theta = (90 - bearing) mod 360``, written in increasing order (BELLHOP3D sorts them).
"""

from __future__ import annotations

import numpy as np

from acoustics.bellhop.envfile import RunSpec, fmt_list, fmt_number
from acoustics.nx2d.box3d import BoxEnvironment
from envdata.area import Absorption, Area


def bellhop3d_bearings(bearing_deg) -> tuple[np.ndarray, np.ndarray]:
    """BELLHOP3D's receiver bearings for tmakit bearings, and where each tmakit bearing lands.

    Parameters
    ----------
    bearing_deg : array_like, shape (N,)
        Distinct bearings, deg clockwise from true north.

    Returns
    -------
    theta_deg : ndarray, shape (N,)
        Counter-clockwise from east, in [0, 360), increasing: the order BELLHOP3D writes them.
    index : ndarray of int, shape (N,)
        ``theta_deg[index[i]]`` is the direction of ``bearing_deg[i]``.
    """
    b = np.asarray(bearing_deg, dtype=float)
    theta = np.mod(90.0 - b, 360.0)
    theta = np.where(np.isclose(theta, 360.0), 0.0, theta)
    order = np.argsort(theta, kind="stable")
    if np.any(np.diff(theta[order]) <= 1e-6):
        raise ValueError(f"bearings: need distinct directions, got {b.tolist()} deg")
    index = np.empty(b.size, dtype=int)
    index[order] = np.arange(b.size)
    return theta[order], index


def coverage_m(box_range_m: float, step_m: float) -> float:
    """How far from the origin along x and y the bottom and the sound speed must reach, m: the
    box, a few ray steps (the step that crosses it) and 1 km more."""
    return box_range_m + 10.0 * step_m + 1000.0


def nx2d_files(area: Area, env: BoxEnvironment, spec: RunSpec, *, bearing_deg, step_m: float,
               box_range_m: float) -> dict[str, str]:
    """The texts of ``{"env": ..., "bty": ..., "ssp": ...}`` of one BELLHOP3D Nx2D run.

    Parameters
    ----------
    area : Area
        The area (bottom half-space, volume absorption).
    env : BoxEnvironment
        Bottom and sound speed on the box about the origin (``box3d.sample_box``).
    spec : RunSpec
        Frequency, source depths (at the origin), receiver depths and ranges, the beam fan.
    bearing_deg : sequence of float
        The radials, deg clockwise from true north (distinct).
    step_m : float
        Ray step, m (> 0).
    box_range_m : float
        Rays stop where |x| or |y| reaches this, m.

    Raises
    ------
    ValueError
        The bottom or sound-speed grid does not reach `coverage_m` about the origin, or the
        bearings are not distinct.
    """
    need = coverage_m(box_range_m, step_m)
    for what, have in (("bathymetry grid", env.bathymetry_half_width_m()),
                       ("sound-speed grid", env.ssp_half_width_m())):
        if have < need:
            raise ValueError(f"BELLHOP3D box: the {what} reaches {have:.0f} m from the origin, less than the "
                             f"{need:.0f} m the rays' box (|x|, |y| < {box_range_m:.0f} m) needs; sample "
                             f"the box wider")
    theta, _ = bellhop3d_bearings(bearing_deg)
    z = env.ssp_depth_m
    depth_max = env.max_depth_m
    at_origin = env.speed_mps[:, int(np.argmin(np.abs(env.ssp_y_m))), int(np.argmin(np.abs(env.ssp_x_m)))]
    volume = "T" if spec.absorption is Absorption.THORP else " "
    bottom = area.bottom
    lines = [f"'{spec.title[:70]}'", fmt_number(spec.freq_hz), "1", f"'HVW{volume}'",
             f"0 0.0 {fmt_number(depth_max)}"]
    lines += [f"{fmt_number(zi)} {fmt_number(ci)} /" for zi, ci in zip(z, at_origin)]
    lines += ["'A~' 0.0",
              f"{fmt_number(depth_max)} {fmt_number(bottom.speed_mps)} {fmt_number(bottom.shear_speed_mps)} "
              f"{fmt_number(bottom.density_gcc)} {fmt_number(bottom.attenuation_db_per_wavelength)} 0.0 /"]
    lines += ["1", "0.0 /", "1", "0.0 /"]  # the source at the origin: x, y in km
    lines += [str(len(spec.source_depth_m)), fmt_list(spec.source_depth_m)]
    lines += [str(len(spec.receiver_depth_m)), fmt_list(spec.receiver_depth_m)]
    range_km = np.asarray(spec.range_m, dtype=float) / 1000.0  # BELLHOP3D reads ranges in km
    lines += [str(len(range_km)), fmt_list(range_km)]
    lines += [str(theta.size), fmt_list(theta)]
    # run type: TL mode, beam type, no beam pattern, point source, rectilinear grid, Nx2D
    lines += [f"'{spec.mode.bellhop_letter}{spec.beam_type} RR2'", str(spec.n_beams),
              f"{fmt_number(spec.angle_min_deg)} {fmt_number(spec.angle_max_deg)} /"]
    lines += [str(theta.size), fmt_list(theta)]  # the bearing fan; Nx2D uses the receiver bearings
    box_depth_m = depth_max * 1.01 + 1.0  # rays leaving this box stop; the bottom reflects first
    box_km = fmt_number(box_range_m / 1000.0)
    lines.append(f"{fmt_number(step_m)} {box_km} {box_km} {fmt_number(box_depth_m)}")
    return {"env": "\n".join(lines) + "\n", "bty": bty_text(env), "ssp": ssp_text(env)}


def bty_text(env: BoxEnvironment) -> str:
    """The 3D bathymetry file: a rectilinear ('R') grid, x and y in km, depths in m."""
    rows = [" ".join(f"{d:.2f}" for d in row) for row in env.bottom_depth_m]
    return "\n".join(["'R'", str(env.x_m.size), _km_list(env.x_m), str(env.y_m.size), _km_list(env.y_m),
                      *rows]) + "\n"


def ssp_text(env: BoxEnvironment) -> str:
    """The hexahedral sound-speed file: x and y in km, depths in m, speeds in m/s."""
    lines = [str(env.ssp_x_m.size), _km_list(env.ssp_x_m), str(env.ssp_y_m.size), _km_list(env.ssp_y_m),
             str(env.ssp_depth_m.size), " ".join(fmt_number(z) for z in env.ssp_depth_m)]
    for plane in env.speed_mps:  # (py, px) at one depth
        lines += [" ".join(f"{c:.3f}" for c in row) for row in plane]
    return "\n".join(lines) + "\n"


def _km_list(values_m) -> str:
    return " ".join(fmt_number(v) for v in np.asarray(values_m, dtype=float) / 1000.0)  # km in the file
