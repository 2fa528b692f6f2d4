"""Tuning of the ML tracker (Grinenkov & Mashoshin 2024); the defaults are the paper's."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True, kw_only=True)
class MLParams:
    """Tuning of the ML tracker; defaults are the paper's."""

    smooth_cycles: int = 19            # L of the robust smoothing (section 4 step 9)
    smooth_drop: int = 2               # dropped at each end of the ranked series
    smooth_passes: int = 1             # 2: smooth the smoothed series again
    rel_course_sd_deg: float = 4.0     # sK_rho of eqs. 9, 25 ("3-5 deg")
    eq30_factor: float = 4.5           # eq. 30
    curvature_factor: float = 4.5      # eq. 8 also needs the bearing's curvature: quadratic term
                                       # of a fit over the tack > this many sd (0: eq. 30 only)
    reverse_course_sd_deg: float = 30.0  # sd of the reverse-bearing relative course in eq. 25
                                         # (conclusion 4: course errors up to 30 deg with it)
    eq25_factor: float = 3.0           # section 4 step 8: bearing change over 3 min > 3 sigma
    eq25_window_s: float = 180.0
    eq25_min_cycles: int = 6           # cycles on the tack before eq. 25 is tried
    maneuver_s: int = 2                # S of eqs. 26-27
    maneuver_l: int = 20               # L of eq. 27
    maneuver_factor: float = 4.5       # eqs. 26, 29
    maneuver_confirm: int = 2          # consecutive cycles a maneuver test must fire
    maneuver_curved: bool = True       # eqs. 26-27 about a quadratic fit of the bearing trace, not
                                       # eq. 27's line (a non-manoeuvring target's trace curves;
                                       # docs/atlas-tracking.md); False: the paper's line
    level_vs_k: bool = True            # eq. 29 on the level less K(r) at the tracked range, against
                                       # the spread that statistic has had on the track and K's
                                       # structure under the range error (tracker.mltma.maneuver.
                                       # level_maneuver_robust); False: the paper's raw level
                                       # against sigma_dW
    level_f: int = 10                  # F of eq. 29
    level_sd_floor_db: float = 0.5     # floor on sigma_dW in eq. 29 (K(r) ripple along range)
    level_history_cycles: int = 30     # eq. 29 on the level less K: the cycles whose statistic
    level_min_history: int = 10        # gives its spread, and the fewest it needs to test
    n_course: int = 24                 # global search: values per axis (>= 20, paper step 8)
    n_speed: int = 20
    speed_span_sd: float = 3.0         # speed axis: mV +- this many sV
    refine_passes: int = 2
    triples: int = 8                   # bearing triples of the eq.-8 least squares
    offsets_n: int = 5                 # eq. 21 quadrature nodes per axis
    range_min_m: float = 100.0
    polish_iters: int = 15            # Gauss-Newton steps on the exact eq. 25 after the search
                                      # (stops early; 6 fell short along the range/speed valley)

    def __post_init__(self) -> None:
        if self.smooth_cycles < 1 or 2 * self.smooth_drop >= self.smooth_cycles:
            raise ValueError(f"smooth_cycles {self.smooth_cycles} must exceed 2 x smooth_drop "
                             f"{self.smooth_drop}")
        if self.n_course < 4 or self.n_speed < 2:
            raise ValueError("n_course >= 4 and n_speed >= 2 are needed")
