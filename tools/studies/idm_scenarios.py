"""The three scenarios of Iglesis & de Montella sec. 5 (and one beyond the paper).

All start with the observer at (0, 0) m, 300 m deep, and the target at (5000, 800) m, 5 m deep,
5 kn on -140 deg (uniform linear motion); a bearing (sd 1.5 deg) and an SPL (sd 4 dB) every
60 s (sec. 5).

- ``idm-maneuvering`` (sec. 5.1, Fig. 2-3): 30 min; the observer at 5 kn on 140 deg turns at a
  constant rate between 13 and 17 min to 20 deg (port turn, 30 deg/min) and holds it.
- ``idm-parallel`` (sec. 5.2, Fig. 4-5): 150 min; the observer at 5 kn on -140 deg, parallel
  to the target (the relative position stays constant; bearings-only is unobservable).
- ``idm-static`` (sec. 5.3, Fig. 6-7, Table 1): 150 min; the observer stays at (0, 0).
- ``idm-static-sl-offset`` (not in the paper): ``idm-static`` with the target 6 dB louder than
  the Ross trend, to show what a joint source-level offset estimate buys.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tracker.rpf.config import KNOT_MPS
from tracker.scenario import ScenarioError


@dataclass(frozen=True, slots=True, kw_only=True)
class IdmScenario:
    """One simulation scenario.

    Attributes
    ----------
    name, title : str
    duration_s, dt_s : float
        Observation period and measurement interval, s.
    obs_speed_mps : float
        Observer speed, m/s (0: static).
    obs_course_deg : float
        Initial observer course, deg.
    turn : tuple of float or None
        (start_s, end_s, final course deg): a constant-rate turn, shortest way round.
    obs_depth_m : float
        Observer depth, m.
    target_x_m, target_y_m, target_depth_m, target_speed_mps, target_course_deg : float
        Target initial position, depth, speed and course.
    bearing_sd_deg, level_sd_db : float
        Measurement noise used to simulate (1.5 deg, 4 dB).
    sl_offset_db : float
        True source level minus the Ross trend, dB (0 in the paper's scenarios).
    report_times_min : tuple of float
        Times printed in the summary (Table 1 for the static observer).
    paper : dict
        The paper's figures for this scenario (RMSE, m, at named times).
    """

    name: str
    title: str
    duration_s: float
    dt_s: float = 60.0
    obs_speed_mps: float = 5.0 * KNOT_MPS
    obs_course_deg: float = 140.0
    turn: tuple[float, float, float] | None = None
    obs_depth_m: float = 300.0
    target_x_m: float = 5000.0
    target_y_m: float = 800.0
    target_depth_m: float = 5.0
    target_speed_mps: float = 5.0 * KNOT_MPS
    target_course_deg: float = -140.0
    bearing_sd_deg: float = 1.5
    level_sd_db: float = 4.0
    sl_offset_db: float = 0.0
    report_times_min: tuple[float, ...] = ()
    paper: dict | None = None

    @property
    def t_s(self) -> np.ndarray:
        """Measurement times, s: 0, dt, ..., duration."""
        return np.arange(0.0, self.duration_s + 0.5 * self.dt_s, self.dt_s)

    def observer_state(self, t_s) -> np.ndarray:
        """Observer (x, y, vx, vy) at times t_s, shape (len(t_s), 4), m and m/s."""
        t = np.asarray(t_s, dtype=float)
        v = self.obs_speed_mps
        c0 = math.radians(self.obs_course_deg)
        if self.turn is None or v == 0.0:
            course = np.full(t.shape, c0)
            x = v * math.sin(c0) * t
            y = v * math.cos(c0) * t
        else:
            t1, t2, c_end_deg = self.turn
            delta = math.radians((c_end_deg - self.obs_course_deg + 180.0) % 360.0 - 180.0)
            rate = delta / (t2 - t1)  # rad/s, shortest way round
            c2 = c0 + delta
            course = np.where(t < t1, c0, np.where(t < t2, c0 + rate * (t - t1), c2))
            # positions integrated exactly: straight, arc at a constant rate, straight
            x1, y1 = v * math.sin(c0) * t1, v * math.cos(c0) * t1
            tau = np.clip(t - t1, 0.0, t2 - t1)
            xa = x1 - v / rate * (np.cos(c0 + rate * tau) - math.cos(c0))
            ya = y1 + v / rate * (np.sin(c0 + rate * tau) - math.sin(c0))
            after = np.maximum(t - t2, 0.0)
            x = np.where(t < t1, v * math.sin(c0) * t, xa + v * math.sin(c2) * after)
            y = np.where(t < t1, v * math.cos(c0) * t, ya + v * math.cos(c2) * after)
        return np.stack([x, y, v * np.sin(course), v * np.cos(course)], axis=-1)

    def target_state(self, t_s) -> np.ndarray:
        """True target (x, y, vx, vy) at times t_s, shape (len(t_s), 4): uniform linear motion."""
        t = np.asarray(t_s, dtype=float)
        c = math.radians(self.target_course_deg)
        vx, vy = self.target_speed_mps * math.sin(c), self.target_speed_mps * math.cos(c)
        return np.stack([self.target_x_m + vx * t, self.target_y_m + vy * t,
                         np.full(t.shape, vx), np.full(t.shape, vy)], axis=-1)


_PAPER_STATIC = {"bot_36min_m": 2857.0, "spl_36min_m": 344.0, "bot_63min_m": 4338.0,
                 "spl_63min_m": 203.0, "bot_150min_m": 13657.0, "spl_150min_m": 1532.0}

SCENARIOS: dict[str, IdmScenario] = {s.name: s for s in (
    IdmScenario(name="idm-maneuvering", title="maneuvering observer (Iglesis & de Montella Fig. 3)",
                duration_s=30 * 60.0, obs_course_deg=140.0, turn=(13 * 60.0, 17 * 60.0, 20.0),
                report_times_min=(13.0, 17.0, 24.0, 30.0),
                paper={"bot_24min_m": 155.0, "spl_24min_m": 85.0, "bot_30min_m": 228.58,
                       "spl_30min_m": 146.17}),
    IdmScenario(name="idm-parallel", title="non-maneuvering observer (Iglesis & de Montella Fig. 5)",
                duration_s=150 * 60.0, obs_course_deg=-140.0,
                report_times_min=(36.0, 63.0, 100.0, 140.0, 150.0),
                paper={"bot_over_spl_150min": 5.7743}),  # "degradation of 477.43 %"
    IdmScenario(name="idm-static", title="static observer (Iglesis & de Montella Fig. 7, Table 1)",
                duration_s=150 * 60.0, obs_speed_mps=0.0, obs_course_deg=0.0,
                report_times_min=(36.0, 63.0, 150.0), paper=_PAPER_STATIC),
    IdmScenario(name="idm-static-sl-offset",
                title="static observer, target 6 dB above the Ross trend (beyond the paper)",
                duration_s=150 * 60.0, obs_speed_mps=0.0, obs_course_deg=0.0, sl_offset_db=6.0,
                report_times_min=(36.0, 63.0, 150.0)),
)}


def get_scenario(name: str) -> IdmScenario:
    """A built-in scenario by name; ScenarioError names the known ones."""
    try:
        return SCENARIOS[name]
    except KeyError:
        raise ScenarioError(f"scenario {name!r}: unknown idm scenario (known: "
                            f"{', '.join(SCENARIOS)})") from None
