"""Simulation scenarios (TOML): observer and target tacks, class, noise and the cycle.

Format (see envdata/scenarios/gm-*.toml)::

    [scenario]
    name = "gm-nps"
    area = "ocean-deep"          # the area whose grid is used (informational check)
    cycle_s = 10.0
    target_class = "NPS"
    bearing_sd_min_deg = 0.0     # optional floor on the simulated bearing sd (eq. 2), deg

    [observer]
    x_m = 0.0                    # start position, m
    y_m = 0.0
    depth_m = 100.0
    [[observer.tacks]]
    course_deg = 90.0
    speed_mps = 2.5
    duration_s = 2400.0

    [target]
    depth_m = 200.0
    detection_range_m = 11200.0       # either this and relative_bearing_deg ...
    relative_bearing_deg = -26.0      # from the observer's heading; negative = to port
    # x_m = ..., y_m = ...            # ... or a start position
    [[target.tacks]]
    course_deg = 270.0
    speed_mps = 4.0
    noise_db = 89.02                  # P0 on this tack, dB re 1 uPa (1 Hz, 1 kHz, 1 m)
    duration_s = 1200.0

Validation uses the area file's rules: unknown keys, wrong types and out-of-range values are
``ScenarioError`` (an ``AreaError``) naming the file, the table and the key.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from envdata.errors import AreaError
from envdata.files import builtin_names, builtin_or_path
from envdata.limits import MAX_POSITION_M, MAX_TIME_S
from envdata.names import check_name
from envdata.tomlfile import TomlTable, read_toml


class ScenarioError(AreaError):
    """A malformed scenario file, an unknown scenario name, or settings a scenario's experiment
    refuses (runs, grid)."""


@dataclass(frozen=True, slots=True, kw_only=True)
class Tack:
    course_deg: float
    speed_mps: float
    duration_s: float
    noise_db: float | None = None  # target tacks only: P0, dB re 1 uPa


@dataclass(frozen=True, slots=True, kw_only=True)
class Scenario:
    name: str
    description: str
    area: str
    cycle_s: float
    target_class: str
    obs_x_m: float
    obs_y_m: float
    obs_depth_m: float
    obs_tacks: tuple[Tack, ...]
    target_depth_m: float
    target_x_m: float
    target_y_m: float
    target_tacks: tuple[Tack, ...]
    bearing_sd_min_deg: float = 0.0
    source: str = "<scenario>"

    @property
    def duration_s(self) -> float:
        return sum(t.duration_s for t in self.target_tacks)

    def times_s(self) -> np.ndarray:
        """Cycle times 0, cycle_s, ... up to the target's last tack end, s."""
        n = int(math.floor(self.duration_s / self.cycle_s + 1e-9))
        return self.cycle_s * np.arange(n + 1, dtype=float)


def tack_path(tacks: tuple[Tack, ...], x0: float, y0: float, t_s: np.ndarray):
    """Positions, course, speed and tack number (1-based) of a tack path at times t_s."""
    t_s = np.asarray(t_s, dtype=float)
    x = np.full(t_s.shape, x0)
    y = np.full(t_s.shape, y0)
    course = np.zeros(t_s.shape)
    speed = np.zeros(t_s.shape)
    tack = np.ones(t_s.shape, dtype=int)
    start = 0.0
    sx, sy = x0, y0
    for j, tk in enumerate(tacks):
        end = start + tk.duration_s
        last = j == len(tacks) - 1
        on = (t_s >= start) & ((t_s < end) | last)
        dt = t_s[on] - start
        a = math.radians(tk.course_deg)
        x[on] = sx + tk.speed_mps * dt * math.sin(a)
        y[on] = sy + tk.speed_mps * dt * math.cos(a)
        course[on] = tk.course_deg
        speed[on] = tk.speed_mps
        tack[on] = j + 1
        sx += tk.speed_mps * tk.duration_s * math.sin(a)
        sy += tk.speed_mps * tk.duration_s * math.cos(a)
        start = end
    return x, y, course, speed, tack


def observer_track(sc: Scenario, t_s):
    """Observer x, y (m), course (deg), speed (m/s) at times t_s."""
    x, y, c, v, _ = tack_path(sc.obs_tacks, sc.obs_x_m, sc.obs_y_m, t_s)
    return x, y, c, v


def target_track(sc: Scenario, t_s):
    """Target x, y (m), course (deg), speed (m/s), P0 (dB) and tack number at times t_s."""
    x, y, c, v, tack = tack_path(sc.target_tacks, sc.target_x_m, sc.target_y_m, t_s)
    noise = np.array([sc.target_tacks[k - 1].noise_db for k in tack], dtype=float)
    return x, y, c, v, noise, tack


def builtin_scenario_names() -> list[str]:
    return builtin_names("scenarios")


def scenario_path(name_or_path) -> Path:
    """Resolve a built-in scenario name or a path to a TOML file."""
    return builtin_or_path(name_or_path, "scenarios", "scenario", ScenarioError)


def load_scenario(name_or_path) -> Scenario:
    """Load a built-in scenario by name or a scenario TOML file; ScenarioError on bad input."""
    try:
        data, source = read_toml(scenario_path(name_or_path), what="scenario file")
        return parse_scenario(data, source)
    except ScenarioError:
        raise
    except AreaError as exc:
        raise ScenarioError(str(exc)) from None


def _tacks(t: TomlTable, key: str, source: str, where: str, *, noise: bool) -> tuple[Tack, ...]:
    raw = t.value(key, required=True)
    if not isinstance(raw, list) or not raw:
        raise ScenarioError(f"{source}: {where}: need at least one [[{where[1:-1]}.{key}]] entry")
    out = []
    for i, item in enumerate(raw):
        tt = TomlTable(item, f"[[{where[1:-1]}.{key}]] #{i + 1}", source)
        course = tt.number("course_deg")
        speed = tt.number("speed_mps")
        duration = tt.number("duration_s")
        p0 = tt.number("noise_db") if noise else None
        tt.done()
        if not 0.0 <= course < 360.0:
            raise ScenarioError(f"{source}: {tt.where} course_deg: must be in [0, 360) deg, "
                                f"got {course}")
        if not 0.0 <= speed <= 30.0:
            raise ScenarioError(f"{source}: {tt.where} speed_mps: must be in [0, 30] m/s, "
                                f"got {speed}")
        if not 0.0 < duration <= 86400.0:
            raise ScenarioError(f"{source}: {tt.where} duration_s: must be in (0, 86400] s, "
                                f"got {duration}")
        if p0 is not None and not 0.0 <= p0 <= 250.0:
            raise ScenarioError(f"{source}: {tt.where} noise_db: must be in [0, 250] dB re 1 uPa, "
                                f"got {p0}")
        out.append(Tack(course_deg=course, speed_mps=speed, duration_s=duration, noise_db=p0))
    return tuple(out)


def parse_scenario(data: dict, source: str = "<scenario>") -> Scenario:
    top = TomlTable(data, "top level", source)
    for key in ("scenario", "observer", "target"):
        top.value(key, required=True)
    top.done()

    t = TomlTable(data["scenario"], "[scenario]", source)
    name = t.wrap(check_name, t.string("name"), "[scenario] name")
    description = t.string("description", "")
    area = t.string("area", "ocean-deep")
    cycle = t.number("cycle_s", 10.0)
    cls = t.string("target_class")
    sd_min = t.number("bearing_sd_min_deg", 0.0)
    t.done()
    if not 0.0 < cycle <= 600.0:
        raise ScenarioError(f"{source}: [scenario] cycle_s: must be in (0, 600] s, got {cycle}")
    if not 0.0 <= sd_min <= 10.0:
        raise ScenarioError(f"{source}: [scenario] bearing_sd_min_deg: must be in [0, 10] deg, "
                            f"got {sd_min}")

    t = TomlTable(data["observer"], "[observer]", source)
    ox, oy = t.number("x_m", 0.0), t.number("y_m", 0.0)
    odepth = t.number("depth_m")
    otacks = _tacks(t, "tacks", source, "[observer]", noise=False)
    t.done()
    if not 0.0 < odepth <= 12000.0:
        raise ScenarioError(f"{source}: [observer] depth_m: must be in (0, 12000] m, got {odepth}")

    t = TomlTable(data["target"], "[target]", source)
    tdepth = t.number("depth_m")
    if t.has("detection_range_m") or t.has("relative_bearing_deg"):
        rng_m = t.number("detection_range_m")
        rel = t.number("relative_bearing_deg")
        if not 0.0 < rng_m <= 1e6:
            raise ScenarioError(f"{source}: [target] detection_range_m: must be in (0, 1e6] m, "
                                f"got {rng_m}")
        if not -180.0 <= rel <= 180.0:
            raise ScenarioError(f"{source}: [target] relative_bearing_deg: must be in "
                                f"[-180, 180] deg, got {rel}")
        b = math.radians(otacks[0].course_deg + rel)
        tx, ty = ox + rng_m * math.sin(b), oy + rng_m * math.cos(b)
    else:
        tx, ty = t.number("x_m"), t.number("y_m")
    ttacks = _tacks(t, "tacks", source, "[target]", noise=True)
    t.done()
    if not 0.0 <= tdepth <= 12000.0:
        raise ScenarioError(f"{source}: [target] depth_m: must be in [0, 12000] m, got {tdepth}")
    for where, tacks in (("[observer] tacks", otacks), ("[target] tacks", ttacks)):
        total = sum(tk.duration_s for tk in tacks)
        if not total <= MAX_TIME_S:
            raise ScenarioError(f"{source}: {where}: {total:g} s in all is beyond 100 years")
    for where, value in (("[observer] x_m", ox), ("[observer] y_m", oy), ("[target] x_m", tx),
                         ("[target] y_m", ty)):
        if not abs(value) <= MAX_POSITION_M:
            raise ScenarioError(f"{source}: {where}: {value:g} m is beyond "
                                f"{MAX_POSITION_M / 1000:g} km of the origin")
    return Scenario(name=name, description=description, area=area, cycle_s=cycle,
                    target_class=cls, obs_x_m=ox, obs_y_m=oy, obs_depth_m=odepth,
                    obs_tacks=otacks, target_depth_m=tdepth, target_x_m=tx, target_y_m=ty,
                    target_tacks=ttacks, bearing_sd_min_deg=sd_min, source=source)
