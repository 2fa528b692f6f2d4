"""The cumulative probability of detection along a track: has the sonar detected the target by
each time (``tmakit plan track``)?

The target's path relative to the observer comes from a scenario (both tracks as
``tmakit simulate`` moves them, without noise) or from a CSV of positions (a truth or track CSV,
or a planned route). The sonar looks once per integration time T of the area's sonar: the path
is taken at t0, t0 + T, ... (linear in time between the file's rows). At each look the signal
excess SE_i = K_i - K_needed (K at the target's bearing and range from the observer, from the
tables where the observer is: ``tracker.simulate.tables_k``, the target at the class's mean
level) and the level's sd split into its persistent and per-look parts
(``acoustics.grid.detectionsigma``) give

    P_cum(t) = E_z[1 - prod_{t_i <= t} (1 - Phi((SE_i + s_i z) / w_i))]      (``acoustics.pd``)

per band: the persistent part (the target's source level, K's offset) drawn once per track, the
per-look part independently at every look. Any band: 1 - prod over bands (1 - P_cum,band), the
bands independent, offsets included; beside it the bound of bands that share one offset (the
source level is one number for all bands): the same integral over every look's every band
(``any_shared``), never more than the independent bands' figure. The expected time of the first
detection is given for the tracks on which it comes (``acoustics.pd.first_detection_times``).
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from acoustics.detection import detection_terms
from acoustics.errors import ObserverPositionError
from acoustics.grid.detectionsigma import LevelSigma, SigmaOverride, detection_sigma_db
from acoustics.grid.face import Tables
from acoustics.pd import any_band, cumulative_pd, first_detection_times, pd_of_excess
from envdata.errors import InputError
from envdata.files import read_csv_text
from envdata.limits import MAX_POSITION_M, MAX_TIME_S
from tracker.errors import MeasurementFileError
from tracker.scenario import Scenario, observer_track, tack_path
from tracker.simulate import TruePaths, tables_k

#: Looks a track may have (one per integration time).
MAX_LOOKS = 200_000
#: The assumptions every result states.
ASSUMPTIONS = (
    "one look per integration time of the sonar; the per-look part of the level independent from look to look",
    "the persistent part (the target's source level, K's offset) drawn once per track: a target quieter than "
    "its class stays quieter",
    "the target at its class's mean level (a scenario's own noise_db is the simulator's truth, not a planner's)",
    "any band: the bands independent of each other, their offsets too (any_shared: one offset for all bands, "
    "the pessimistic bound)",
)


@dataclass(frozen=True, slots=True, kw_only=True)
class TrackPath:
    """Where target and observer are at times, plane coordinates of the area's origin, m.

    Attributes
    ----------
    t_s, obs_x_m, obs_y_m, x_m, y_m : ndarray, shape (T,)
    obs_depth_m : float or None
        The observer's depth (None: the tables' observer depth).
    target_depth_m : float or None
        The target's (None: its class's).
    cls_name : str or None
        The class the path names (a scenario's, or a CSV's one class).
    source : str
    observer_given : bool
        False where the file gave no observer position (then at the origin).
    """

    t_s: np.ndarray
    obs_x_m: np.ndarray
    obs_y_m: np.ndarray
    x_m: np.ndarray
    y_m: np.ndarray
    obs_depth_m: float | None
    target_depth_m: float | None
    cls_name: str | None
    source: str
    observer_given: bool = True

    def at(self, t_s: np.ndarray) -> TrackPath:
        """The path at other times, linear in time between its own (held beyond its ends)."""
        def lin(v):
            return np.interp(t_s, self.t_s, v) if self.t_s.size > 1 else np.full(t_s.shape, v[0])

        return TrackPath(t_s=t_s, obs_x_m=lin(self.obs_x_m), obs_y_m=lin(self.obs_y_m), x_m=lin(self.x_m),
                         y_m=lin(self.y_m), obs_depth_m=self.obs_depth_m, target_depth_m=self.target_depth_m,
                         cls_name=self.cls_name, source=self.source, observer_given=self.observer_given)


def scenario_path(sc: Scenario) -> TrackPath:
    """A scenario's observer and target tracks at its cycle times, without noise."""
    t = sc.times_s()
    ox, oy, _, _ = observer_track(sc, t)
    x, y, _, _, _ = tack_path(sc.target_tacks, sc.target_x_m, sc.target_y_m, t)
    return TrackPath(t_s=t, obs_x_m=ox, obs_y_m=oy, x_m=x, y_m=y, obs_depth_m=sc.obs_depth_m,
                     target_depth_m=sc.target_depth_m, cls_name=sc.target_class, source=sc.source)


def read_track_path(path: str | Path, cls_name: str | None = None) -> TrackPath:
    """A path from a CSV: ``t_s`` and the target as ``range_m, bearing_deg`` from the observer or
    as ``x_m, y_m``; optional ``obs_x_m, obs_y_m`` (else the observer at the origin),
    ``obs_depth_m`` and ``class`` (a track CSV's class hypotheses: the rows of ``cls_name``).

    Raises
    ------
    InputError
        A file that is not such a CSV, a missing or non-numeric column, a value out of range,
        times not increasing, or a class not in the file.
    """
    where = str(path)
    text = read_csv_text(path, "track CSV", MeasurementFileError)
    try:
        df = pd.read_csv(io.StringIO(text), dtype={"class": str}, comment="#")
    except (pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
        raise MeasurementFileError(f"{where}: not a CSV track ({str(exc).splitlines()[0][:80]})") from None
    df.columns = [str(c).strip() for c in df.columns]
    if "class" in df.columns:
        classes = sorted(set(df["class"].dropna().astype(str)))
        if cls_name is None and len(classes) > 1:
            raise MeasurementFileError(f"{where}: rows of several classes ({', '.join(classes)}); "
                                       f"say which with --class")
        cls_name = cls_name if cls_name is not None else (classes[0] if classes else None)
        if cls_name not in classes:
            raise MeasurementFileError(f"{where}: no rows of class {cls_name!r} "
                                       f"(classes: {', '.join(classes) or 'none'})")
        df = df[df["class"].astype(str) == cls_name]
    relative = {"range_m", "bearing_deg"} <= set(df.columns)
    need = ["t_s", *(("range_m", "bearing_deg") if relative else ("x_m", "y_m"))]
    missing = [c for c in need if c not in df.columns]
    if missing:
        raise MeasurementFileError(f"{where}: missing column {missing[0]!r} (a track needs t_s and either range_m, "
                                   f"bearing_deg from the observer or x_m, y_m; optional obs_x_m, obs_y_m, "
                                   f"obs_depth_m, class)")
    observer = {"obs_x_m", "obs_y_m"} & set(df.columns)
    if len(observer) == 1:
        raise MeasurementFileError(f"{where}: {observer.pop()} without its pair; give both obs_x_m and obs_y_m, "
                                   f"or neither")
    cols = need + sorted(observer) + (["obs_depth_m"] if "obs_depth_m" in df.columns else [])
    if not len(df):
        raise MeasurementFileError(f"{where}: no rows")
    values = {c: _numeric(df[c], c, where) for c in cols}
    t = values["t_s"]
    if np.any(np.abs(t) > MAX_TIME_S) or (t.size > 1 and np.any(np.diff(t) <= 0)):
        raise MeasurementFileError(f"{where}: t_s must increase from row to row and stay within 100 years")
    ox = values.get("obs_x_m", np.zeros(t.size))
    oy = values.get("obs_y_m", np.zeros(t.size))
    if relative:
        if np.any(values["range_m"] < 0) or np.any(np.abs(values["bearing_deg"]) > 1e4):
            raise MeasurementFileError(f"{where}: range_m must be >= 0 m and bearing_deg a bearing in degrees")
        a = np.radians(values["bearing_deg"])
        x, y = ox + values["range_m"] * np.sin(a), oy + values["range_m"] * np.cos(a)
    else:
        x, y = values["x_m"], values["y_m"]
    for name, v in (("x_m", x), ("y_m", y), ("obs_x_m", ox), ("obs_y_m", oy)):
        if np.any(np.abs(v) > MAX_POSITION_M):
            raise MeasurementFileError(f"{where}: {name}: a position beyond {MAX_POSITION_M / 1000:g} km of the origin")
    depth = values.get("obs_depth_m")
    if depth is not None and (np.ptp(depth) > 0 or not 0 <= depth[0] <= 12_000):
        raise MeasurementFileError(f"{where}: obs_depth_m must be one depth, 0-12000 m, on every row")
    return TrackPath(t_s=t, obs_x_m=ox, obs_y_m=oy, x_m=x, y_m=y,
                     obs_depth_m=None if depth is None else float(depth[0]), target_depth_m=None,
                     cls_name=cls_name, source=where, observer_given=bool(observer))


def _numeric(column: pd.Series, name: str, where: str) -> np.ndarray:
    values = pd.to_numeric(column, errors="coerce").to_numpy(dtype=float)
    bad = ~np.isfinite(values)
    if bad.any():
        row = int(np.flatnonzero(bad)[0])
        raise MeasurementFileError(f"{where}: column {name!r}, row {row + 1}: {column.iloc[row]!r} is not a "
                                   f"finite number")
    return values


@dataclass(frozen=True, slots=True, kw_only=True)
class TrackPD:
    """P_D along a track, per band and any band (``rows``), at each look.

    Attributes
    ----------
    path : TrackPath
        The path at the looks.
    range_m, bearing_deg : ndarray, shape (T,)
        The target from the observer.
    rows : tuple of str
        The bands, then "any".
    pd : ndarray, shape (T, M + 1)
        P_D of each look alone.
    cumulative : ndarray, shape (T, M + 1)
        P(detected at one of the looks so far).
    cumulative_shared : ndarray, shape (T,)
        P(detected in any band by then) with one offset shared by the bands (module docstring).
    first : dict
        row -> ``acoustics.pd.first_detection_times`` (and ``"any_shared"``).
    look_s : float
        The time between looks, s (the sonar's integration time).
    sigma_source : str
    """

    path: TrackPath
    range_m: np.ndarray
    bearing_deg: np.ndarray
    rows: tuple[str, ...]
    pd: np.ndarray
    cumulative: np.ndarray
    cumulative_shared: np.ndarray
    first: dict
    look_s: float
    sigma_source: str

    def table(self) -> pd.DataFrame:
        """The looks as the CSV ``tmakit plan track`` writes (docs/formats.md "P_D along a track")."""
        p = self.path
        out = pd.DataFrame({"t_s": p.t_s, "obs_x_m": p.obs_x_m, "obs_y_m": p.obs_y_m, "x_m": p.x_m, "y_m": p.y_m,
                            "range_m": self.range_m, "bearing_deg": self.bearing_deg})
        for i, row in enumerate(self.rows):
            out[f"pd_{row}"] = self.pd[:, i]
        for i, row in enumerate(self.rows):
            out[f"cum_pd_{row}"] = self.cumulative[:, i]
        out["cum_pd_any_shared"] = self.cumulative_shared
        return out


def look_times(t_s: np.ndarray, look_s: float) -> np.ndarray:
    """t0, t0 + T, ... up to the path's last time."""
    n = int(math.floor((t_s[-1] - t_s[0]) / look_s + 1e-9)) + 1
    if n > MAX_LOOKS:
        raise InputError(f"the track lasts {t_s[-1] - t_s[0]:g} s: {n} looks of {look_s:g} s, more than "
                         f"{MAX_LOOKS}")
    return t_s[0] + look_s * np.arange(n)


def track_pd(tables: Tables, path: TrackPath, cls_name: str, *, override: SigmaOverride | None = None) -> TrackPD:
    """P_D and the cumulative P_D of a class along a path (module docstring).

    Raises
    ------
    InputError
        A class not in the tables, or a path the tables cannot serve (an observer outside an
        atlas's positions, a depth they do not hold).
    """
    ic = tables.class_index(cls_name)
    cls = tables.classes[ic]
    look_s = float(tables.area.sonar.integration_time_s)
    looks = path.at(look_times(path.t_s, look_s))
    obs_depth = tables.observer_depth_m if looks.obs_depth_m is None else looks.obs_depth_m
    if tables.outside_depth(obs_depth):
        raise InputError(f"{path.source}: observer depth {tables.depth_problem(obs_depth)}")
    try:
        tables.check_observers(looks.obs_x_m, looks.obs_y_m)
    except ObserverPositionError as exc:  # the position's index is the look's
        raise InputError(f"{path.source}: the observer at t = {looks.t_s[exc.index]:g} s: {exc.reason}") from None
    dx, dy = looks.x_m - looks.obs_x_m, looks.y_m - looks.obs_y_m
    rng = np.hypot(dx, dy)
    bearing = np.mod(np.degrees(np.arctan2(dx, dy)), 360.0)
    depth = cls.depth_m if looks.target_depth_m is None else looks.target_depth_m
    k = tables_k(tables)(TruePaths(ic=ic, obs_x_m=looks.obs_x_m, obs_y_m=looks.obs_y_m, obs_depth_m=obs_depth,
                                   x_m=looks.x_m[None], y_m=looks.y_m[None], range_m=rng[None],
                                   bearing_deg=bearing[None], target_depth_m=depth))[0]        # (T, M)
    terms = detection_terms(tables.area, cls, tables.bands)
    excess = k - terms.k_needed_db()[None, :]
    sigma = _sigma_along(tables, ic, looks, rng, bearing, override)
    p_bands = pd_of_excess(excess, sigma.total_db)
    cum = np.stack([cumulative_pd(excess[:, b], sigma.persistent_db[:, b], sigma.per_look_db[:, b])
                    for b in range(len(tables.bands))], axis=1)
    pd_all = np.concatenate([p_bands, any_band(p_bands, axis=1)[:, None]], axis=1)
    cum_all = np.concatenate([cum, any_band(cum, axis=1)[:, None]], axis=1)
    # one offset for every band: the looks' bands in a row, one integral (every M-th value: a look's end)
    m = len(tables.bands)
    shared = cumulative_pd(excess.ravel(), sigma.persistent_db.ravel(), sigma.per_look_db.ravel())[m - 1::m]
    rows = (*tables.band_names, "any")
    first = {row: first_detection_times(looks.t_s, cum_all[:, i]) for i, row in enumerate(rows)}
    first["any_shared"] = first_detection_times(looks.t_s, shared)
    return TrackPD(path=looks, range_m=rng, bearing_deg=bearing, rows=rows, pd=pd_all, cumulative=cum_all,
                   cumulative_shared=shared, first=first, look_s=look_s, sigma_source=sigma.source)


def _sigma_along(tables: Tables, ic: int, looks: TrackPath, rng: np.ndarray, bearing: np.ndarray, override):
    """The level's sd at every look, from the tables where the observer is then."""
    views = [tables.at_observer(x, y) for x, y in zip(looks.obs_x_m, looks.obs_y_m)]
    if all(v is views[0] for v in views):
        return detection_sigma_db(views[0], ic, rng, bearing, override)
    parts = [detection_sigma_db(v, ic, rng[i:i + 1], bearing[i:i + 1], override) for i, v in enumerate(views)]
    return LevelSigma(persistent_db=np.concatenate([p.persistent_db for p in parts]),
                      per_look_db=np.concatenate([p.per_look_db for p in parts]), source=parts[0].source)


def track_pd_figure(result: TrackPD):
    """The cumulative P_D against time per band and any band, each look's own P_D, and the range.

    Artists carry ``gid``s ``cum:ROW``, ``cum:any_shared`` and ``look:ROW`` (minutes, P_D) and
    ``range`` (minutes, km).
    """
    import matplotlib

    from acoustics.plots.figures import new_figure

    t_min = (result.path.t_s - result.path.t_s[0]) / 60.0
    fig = new_figure(figsize=(9.0, 6.2), layout="constrained")
    ax, rax = fig.subplots(2, 1, sharex=True, height_ratios=[3, 1])
    colors = matplotlib.colormaps["tab10"]
    for i, row in enumerate(result.rows):
        any_row = row == "any"
        color = "k" if any_row else colors(i)
        line, = ax.plot(t_min, result.cumulative[:, i], color=color, lw=2.4 if any_row else 1.3,
                        label=f"{'any band' if any_row else row}: cumulative")
        line.set_gid(f"cum:{row}")
        look, = ax.plot(t_min, result.pd[:, i], color=color, lw=0.8, ls=":", alpha=0.8)
        look.set_gid(f"look:{row}")
    shared, = ax.plot(t_min, result.cumulative_shared, color="k", lw=1.4, ls="--",
                      label="any band, one offset shared by the bands")
    shared.set_gid("cum:any_shared")
    first = result.first["any"]
    for key, level in (("median_s", 0.5), ("p90_s", 0.9)):
        if first[key] is not None:
            ax.axvline((first[key] - result.path.t_s[0]) / 60.0, color="0.4", lw=0.8, ls="--")
            ax.annotate(f"P_cum {level:g}", ((first[key] - result.path.t_s[0]) / 60.0, level), xytext=(4, -12),
                        textcoords="offset points", fontsize=8)
    ax.set_ylim(-0.02, 1.02)
    ax.set_ylabel("P(detected by then)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7.5, loc="lower right", title="dotted: one look's own P_D", title_fontsize=7.5)
    mean = first["mean_s_given_detected"]
    ax.set_title(f"class {result.path.cls_name}: P(detected by the end) {first['p_detected_by_end']:.3f} (any band); "
                 + (f"mean time of the first detection, given one, {mean / 60:.1f} min" if mean is not None
                    else "no detection expected") + f"\nlooks every {result.look_s:g} s; \u03c3: "
                 f"{result.sigma_source}", fontsize=8.5)
    line, = rax.plot(t_min, result.range_m / 1000.0, color="0.2")
    line.set_gid("range")
    rax.set_ylabel("range, km")
    rax.set_xlabel(f"time from {result.path.t_s[0]:g} s, min")
    rax.grid(alpha=0.3)
    fig.suptitle(f"Cumulative probability of detection along {Path(result.path.source).name}", fontsize=10)
    return fig


__all__ = ["ASSUMPTIONS", "TrackPD", "TrackPath", "read_track_path", "scenario_path", "track_pd", "track_pd_figure"]
