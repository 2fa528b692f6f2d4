"""A Stone Soup measurement model whose level function is tmakit's: bearing and band levels.

The state is Stone Soup's constant-velocity one, (x, vx, y, vy) in metres and m/s east and north
of the area's origin (the local plane of the grid's area, docs/formats.md). The measurement is

    z = (bearing, W_1, ..., W_m),   bearing = atan2(x - x_o, y - y_o) (clockwise from north),
                                    W_b = P0 + K_b(r, bearing, depth, observer) + H   (eq. 12)

for the bands the detection holds, P0 the class's level (its mean ``noise_mean_db``, or for a
Ross class 170 + 53 lg(v / 5.14 m/s) at the state's own speed, eq. 12 of Iglesis & de Montella),
K from the grid or atlas face (``acoustics.open_tables``; an atlas's tables where the observer
is) at the observer's depth, H the sonar's receiver gain. The noise is Gaussian: the bearing's
sd, and between the bands the covariance of one cycle's level errors as the one level model has
it (`tracker.levels.LevelErrors.of_tables`: the source level's sd and K's offset and residual,
the part common to the bands correlated between them, each grown with the observer's distance
from where tables of one position were computed) plus the level measurement's own variance on
the diagonal. A Stone Soup filter counts each detection's errors anew: the offset that persists
along a track is integrated out only by tmakit's own trackers (`tracker.levels`). ``logpdf``
evaluates every particle at once.
"""

from __future__ import annotations

import math

import numpy as np
from stonesoup.base import Property
from stonesoup.models.measurement.nonlinear import NonLinearGaussianMeasurement
from stonesoup.types.array import CovarianceMatrix, StateVector, StateVectors

from envdata.classes import SourceLevelModel, ross_source_level_db
from tracker.levels import LevelErrors

#: A state's position and velocity rows in Stone Soup's (x, vx, y, vy).
X, VX, Y, VY = 0, 1, 2, 3


def geometry(state_vector, observer_x_m: float, observer_y_m: float
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Bearing (rad, clockwise from north), range (m) and speed (m/s) of states (4, N) from an
    observer."""
    sv = np.asarray(state_vector, dtype=float).reshape(4, -1)
    dx, dy = sv[X] - observer_x_m, sv[Y] - observer_y_m
    return np.arctan2(dx, dy), np.hypot(dx, dy), np.hypot(sv[VX], sv[VY])


def source_level_db(cls, speed_mps: np.ndarray) -> np.ndarray:
    """The class's source level at each state's speed: Ross's for a Ross class, else its mean."""
    if cls.source_level_model is SourceLevelModel.ROSS:
        return ross_source_level_db(speed_mps)
    return np.full(np.shape(speed_mps), float(cls.noise_mean_db))


class TablesMeasurementModel(NonLinearGaussianMeasurement):
    """Bearing (rad, clockwise from north) and band levels (dB re 1 uPa) from tmakit's tables,
    for one detection: the observer where it was, the bands it holds."""

    tables: object = Property(doc="The grid face (acoustics.open_tables) at the observer's position")
    class_index: int = Property(doc="The target class's index in the tables")
    band_index: tuple = Property(doc="The tables' indices of the bands the measurement holds, in its order")
    observer_x_m: float = Property(doc="Observer east of the area's origin, m")
    observer_y_m: float = Property(doc="Observer north of the area's origin, m")
    observer_depth_m: float = Property(doc="Observer depth, m")
    bearing_sd_rad: float = Property(doc="Bearing error sd, rad")
    level_sd_db: float = Property(doc="Level measurement error sd, dB (beside the source level's and K's)")
    noise_covar: CovarianceMatrix = Property(default=None, doc="The noise at the tables' typical K error "
                                                                 "(logpdf takes K's at each state's range)")
    mapping: tuple = Property(default=(X, Y), doc="The position rows of the state")

    def __init__(self, *args, **kwargs):
        tables, ic = kwargs["tables"], kwargs["class_index"]
        cls = tables.classes[ic]
        bands = list(kwargs["band_index"])
        away = tables.distance_from_origin_m(kwargs["observer_x_m"], kwargs["observer_y_m"])
        errors = LevelErrors.of_tables(tables, ic, bands, source_sd_db=cls.noise_sd_db)
        level_cov = errors.cycle_covariance(len(bands), 0.0 if away is None else float(away))
        level_cov = level_cov + kwargs["level_sd_db"] ** 2 * np.eye(len(bands))
        if kwargs.get("noise_covar") is None:  # Stone Soup checks it on construction
            cov = np.zeros((1 + len(bands),) * 2)
            cov[0, 0] = kwargs["bearing_sd_rad"] ** 2
            cov[1:, 1:] = level_cov
            kwargs["noise_covar"] = CovarianceMatrix(cov)
        super().__init__(*args, **kwargs)
        self._cls = cls
        self._level_cov = level_cov

    @property
    def ndim_state(self) -> int:
        return 4

    @property
    def ndim_meas(self) -> int:
        return 1 + len(self.band_index)

    def _geometry(self, state_vector) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return geometry(state_vector, self.observer_x_m, self.observer_y_m)

    def levels_db(self, state_vector) -> np.ndarray:
        """W of each band of the measurement for states (4, N): shape (bands, N), dB."""
        bearing, rng, speed = self._geometry(state_vector)
        k = self.tables.k_at(self.class_index, rng, depth_m=self.observer_depth_m,
                             bearing_deg=np.degrees(bearing) % 360.0)         # (N, M)
        k = np.atleast_2d(k)[:, list(self.band_index)].T                       # (bands, N)
        return source_level_db(self._cls, speed)[None, :] + k + self.tables.area.sonar.receiver_gain_db

    def function(self, state, noise=False, **kwargs) -> StateVector | StateVectors:
        """The measurement of ``state`` (its particles at once)."""
        sv = np.asarray(state.state_vector, dtype=float)
        single = sv.ndim == 1 or sv.shape[1] == 1
        sv = sv.reshape(4, -1)
        bearing, _, _ = self._geometry(sv)
        out = np.vstack([bearing[None, :], self.levels_db(sv)])
        if noise is True:
            out = out + self.rvs(num_samples=out.shape[1], **kwargs)
        elif noise is not False:
            out = out + np.asarray(noise)
        return StateVector(out[:, 0]) if single else StateVectors(out)

    def logpdf(self, state1, state2, **kwargs) -> float | np.ndarray:
        """Log likelihood of the measurement ``state1`` for the states of ``state2`` (each particle),
        the bearing residual wrapped to (-pi, pi], the levels with their covariance between bands
        (module docstring)."""
        z = np.asarray(state1.state_vector, dtype=float).ravel()
        sv = np.asarray(state2.state_vector, dtype=float).reshape(4, -1)
        bearing, _, _ = self._geometry(sv)
        d_b = np.mod(z[0] - bearing + math.pi, 2.0 * math.pi) - math.pi
        out = -0.5 * (d_b ** 2 / self.bearing_sd_rad ** 2 + math.log(2.0 * math.pi * self.bearing_sd_rad ** 2))
        if len(self.band_index):
            d_l = z[1:, None] - self.levels_db(sv)
            # a state where the grid has no K (beyond land) explains no level
            d_l = np.where(np.isfinite(d_l), d_l, 1e3)
            chol = np.linalg.cholesky(self._level_cov)
            w = np.linalg.solve(chol, d_l)
            logdet = 2.0 * float(np.log(np.diag(chol)).sum())
            out = out - 0.5 * (np.sum(w * w, axis=0) + logdet + d_l.shape[0] * math.log(2.0 * math.pi))
        return out if out.size > 1 else float(out[0])

    def pdf(self, state1, state2, **kwargs):
        return np.exp(self.logpdf(state1, state2, **kwargs))
