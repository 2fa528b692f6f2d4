"""An area's radials by BELLHOP3D's Nx2D mode: one run per frequency covers every bearing.

The alternative to ``acoustics.builder.radial``'s one 2-D BELLHOP run per radial and frequency
(docs/nx2d.md compares the two). The environment is sampled once on a Cartesian box about the
origin (``box3d``), each run frequency gets one BELLHOP3D run (``env3d``) whose receivers,
ranges, beam fan and ray step are those of the 2-D runs, and its multi-bearing shade file
(``shd3d``) gives the pressure along every radial. ``bearing_groups`` cuts each frequency's
bearings into that many runs, so that runs of one frequency can go to different workers.

``nx2d_fields`` returns, per run frequency, the pressure as (bearing, receiver depth, range) in
the area's bearing order: what ``acoustics.builder.radial`` gets from its 2-D runs, radial by radial.
"""

from __future__ import annotations

import functools
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from acoustics.bellhop.exe import find_bellhop3d
from acoustics.bellhop.runner import BASE, run_env
from acoustics.builder.bandruns import field_run_frequencies_hz, run_timeout_s
from acoustics.builder.executor import TaskStats, run_tasks
from acoustics.builder.plan import run_spec
from acoustics.builder.radial import BOX_MARGIN, DEFAULT_STEP_M
from acoustics.builder.runs import Run
from acoustics.errors import BellhopError
from acoustics.nx2d.box3d import BoxEnvironment, sample_box
from acoustics.nx2d.env3d import bellhop3d_bearings, coverage_m, nx2d_files
from acoustics.nx2d.shd3d import read_shd3d
from envdata.area import Area


@dataclass(frozen=True)
class Nx2dRun:
    """One BELLHOP3D run: a frequency and the area's bearings (indices) it covers.

    ``theta_deg`` are those bearings as BELLHOP3D holds them (``env3d.bellhop3d_bearings``:
    counter-clockwise from east, increasing) and ``theta_index[i]`` the place of the run's i-th
    bearing among them.
    """

    run: Run
    freq_hz: float
    bearings: tuple[int, ...]
    theta_deg: tuple[float, ...]
    theta_index: tuple[int, ...]


@dataclass
class Nx2dStats:
    """Timings of an Nx2D computation, s."""

    sample_seconds: float = 0.0   # the box's bottom and sound speed from the data files
    write_seconds: float = 0.0    # the .env/.bty/.ssp texts
    bellhop_seconds: float = 0.0  # sum of the BELLHOP3D process wall times
    wall_seconds: float = 0.0     # the runs, start to end (parallel with workers > 1)
    runs: int = 0
    run_seconds: list[float] = field(default_factory=list)


def box_range_m(area: Area) -> float:
    """Rays stop where |x| or |y| reaches this, m: the 2-D runs' range box (``radialgrid.BOX_MARGIN``)."""
    return float(area.grid.range_m().max()) * BOX_MARGIN[0] + BOX_MARGIN[1]


def ray_step_m(area: Area) -> float:
    """The area's ``[propagation] step_m``, else the 2-D runs' default, m."""
    prop = area.propagation
    return prop.step_m if prop.step_m is not None else DEFAULT_STEP_M


def sample_area_box(area: Area, **kwargs) -> BoxEnvironment:
    """The area's environment on a box wide enough for its Nx2D runs (``box3d.sample_box``)."""
    return sample_box(area, coverage_m(box_range_m(area), ray_step_m(area)), **kwargs)


def plan_nx2d_runs(area: Area, env: BoxEnvironment, receivers_m, *, bearing_groups: int = 1) -> list[Nx2dRun]:
    """The BELLHOP3D runs of every run frequency (``bearing_groups`` runs each).

    The source is at the observer's depth at the origin; receivers at ``receivers_m`` and the
    grid's ranges; the beam fan, mode and ray step are the area's, as in the 2-D runs.
    """
    prop = area.propagation
    bearings = area.bearings.bearing_deg
    if not 1 <= bearing_groups <= len(bearings):
        raise ValueError(f"bearing_groups: must be in [1, {len(bearings)}], got {bearing_groups}")
    rng = area.grid.range_m()
    receivers = tuple(float(z) for z in receivers_m)
    freqs = field_run_frequencies_hz(area)  # the 2-D runs' own (one run for every band where it serves)
    groups = [tuple(int(i) for i in g) for g in np.array_split(np.arange(len(bearings)), bearing_groups)]
    out = []
    for f in freqs:
        for group in groups:
            spec = run_spec(area, title=f"tmakit {area.name} Nx2D f={f:.3f} Hz bearings {group[0] + 1}-{group[-1] + 1}",
                            freq_hz=f, source_depths_m=(area.observer.depth_m,), receiver_depths_m=receivers,
                            ranges_m=rng)
            files = nx2d_files(area, env, spec, bearing_deg=[bearings[i] for i in group],
                               step_m=ray_step_m(area), box_range_m=box_range_m(area))
            run = Run(env=files["env"], files=(("bty", files["bty"]), ("ssp", files["ssp"])), freq_hz=f,
                      source_depth_m=area.observer.depth_m, n_beams=prop.n_beams * len(group),
                      timeout_s=run_timeout_s(area, prop.n_beams * len(group), len(receivers) * rng.size))
            theta, index = bellhop3d_bearings([bearings[i] for i in group])
            out.append(Nx2dRun(run=run, freq_hz=f, bearings=group, theta_deg=tuple(float(t) for t in theta),
                               theta_index=tuple(int(i) for i in index)))
    return out


def execute_nx2d_run(item: Nx2dRun, exe: str | None = None) -> tuple[np.ndarray, float]:
    """Run one BELLHOP3D environment; its pressure (bearing of ``item``, receiver, range), complex64,
    in the order of ``item.bearings``, and BELLHOP3D's time.

    Raises BellhopError with BELLHOP3D's own message (from ``runner.run_env``), or when the shade
    file is unreadable or holds other bearings than were asked for.
    """
    exe = exe if exe is not None else str(find_bellhop3d().path)
    run = item.run
    with tempfile.TemporaryDirectory(prefix="tmakit-bellhop3d-") as tmp:
        result = run_env(run.env, exe=exe, keep_dir=tmp, files=dict(run.files), timeout_s=run.timeout_s)
        shade = read_shd3d(Path(tmp) / f"{BASE}.shd")
    theta = np.array(item.theta_deg)
    if shade.bearing_deg.shape != theta.shape or not np.allclose(shade.bearing_deg, theta, rtol=0, atol=1e-3):
        raise BellhopError(f"BELLHOP3D wrote bearings {shade.bearing_deg.tolist()} deg to its shade file, "
                           f"asked for {theta.tolist()} deg", prt_text=result.prt_text)
    # BELLHOP3D's order is theta = 90 - bearing, sorted; back to the run's own order
    return shade.pressure[list(item.theta_index), 0], result.seconds


def theta_to_bearing(theta_deg) -> np.ndarray:
    """BELLHOP3D bearings (counter-clockwise from east) as tmakit's (clockwise from north), deg."""
    return np.mod(90.0 - np.asarray(theta_deg, dtype=float), 360.0)


def nx2d_fields(area: Area, receivers_m, *, workers: int = 1, bearing_groups: int = 1,
                env: BoxEnvironment | None = None, exe: str | None = None,
                stats: Nx2dStats | None = None) -> dict[float, np.ndarray]:
    """Pressure along every radial by BELLHOP3D Nx2D: {run frequency: (bearing, receiver, range)}.

    Parameters
    ----------
    area : Area
        An area with ``[origin]`` and ``[bearings]``.
    receivers_m : array_like
        Receiver depths, m (``acoustics.builder.radial`` uses its depth axis plus the class depths).
    workers : int
        BELLHOP3D processes at once.
    bearing_groups : int
        Runs per frequency, each with a share of the bearings.
    env : BoxEnvironment, optional
        The sampled box (default: ``sample_area_box(area)``).
    exe : str, optional
        BELLHOP3D (default: ``find_bellhop3d()``).
    stats : Nx2dStats, optional
        Filled with timings.
    """
    stats = stats if stats is not None else Nx2dStats()
    exe = exe if exe is not None else str(find_bellhop3d().path)
    if env is None:
        start = time.perf_counter()
        env = sample_area_box(area)
        stats.sample_seconds = time.perf_counter() - start
    start = time.perf_counter()
    items = plan_nx2d_runs(area, env, receivers_m, bearing_groups=bearing_groups)
    stats.write_seconds = time.perf_counter() - start
    n_bearing = len(area.bearings.bearing_deg)
    fields: dict[float, np.ndarray] = {}
    done = TaskStats()
    longest_first = sorted(items, key=lambda item: -item.run.n_beams)
    tasks = run_tasks(functools.partial(execute_nx2d_run, exe=exe), longest_first, key=lambda item: item.run.key,
                      workers=workers, desc="BELLHOP3D runs", unit="run", stats=done)
    for item, (pressure, seconds), _ in tasks:
        if item.freq_hz not in fields:
            fields[item.freq_hz] = np.zeros((n_bearing,) + pressure.shape[1:], dtype=np.complex64)
        fields[item.freq_hz][list(item.bearings)] = pressure
        stats.bellhop_seconds += seconds
        stats.run_seconds.append(seconds)
    stats.runs = done.total
    stats.wall_seconds = done.wall_seconds
    return fields
