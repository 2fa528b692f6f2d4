"""From a measurement CSV to track rows (``tmakit track --method rpf|rpf-bot|rpf-vp``).

`track_measurements` picks the band and class hypotheses, turns the `Measurements` into the
arrays `tracker.rpf.batch.run_batch` filters, and the estimates into the rows of a track file.
"""

from __future__ import annotations

import logging
import math
from dataclasses import replace

import numpy as np

from tracker.levels import MEASUREMENT_SD_DB
from tracker.methods import Method
from tracker.rpf.batch import run_batch
from tracker.rpf.config import BEARINGS_ONLY_SIGMA_A_MIX_MPS2, RpfConfig
from tracker.rpf.likelihood import bearing_rad

log = logging.getLogger(__name__)


def track_measurements(tables, measurements, *, method: str, rng: np.random.Generator,
                       cls_name: str | None = None, band: str | None = None,
                       config: RpfConfig | None = None, depth_unknown: bool = False,
                       integrate_errors: bool = True, range_span_m: tuple[float, float] | None = None):
    """Track one target from a measurement CSV with the RPF; one row per cycle per class.

    The measurements are checked against the grid by ``tracker.track.track``, the way in.

    Parameters
    ----------
    tables : acoustics.grid.face.Tables
        The propagation grid's tables.
    measurements : tracker.measurements.Measurements
        Bearings and band levels. ``rpf`` needs the ``level_db_NAME`` column of the band; a
        blank level uses the bearing alone that cycle, a blank bearing the level alone.
    method : {"rpf", "rpf-bot", "rpf-vp"}
        Bearings and SPL, bearings only, or bearings and SPL with the variance-preserving
        regularization (``RpfConfig.shrink``).
    rng : numpy.random.Generator
        Seeded generator: same seed, same track.
    cls_name : str, optional
        Class hypothesis (source level model and depth); default every class of the grid.
    band : str, optional
        Band whose level is the SPL; default the first grid band with a level column.
    config : RpfConfig, optional
        Filter settings; default `command_config` (the range prior log-uniform over
        ``range_span_m``, 20 000 particles, three acceleration sds, a quarter of the paper's
        bandwidth, sigma_l the level's own error). Each class hypothesis's filter takes that
        class's speed mean and sd as its speed prior (the paper's 3 +- 2 kn are its scenario's;
        docs/uncertainty.md, "The command's particle filters"); ``rpf-bot`` without a class the
        grid's classes pooled. A ``bearing_sigma_deg`` column gives each cycle's bearing its own
        sd (sigma_theta where blank: its median).
    depth_unknown : bool
        The target's depth unknown: a bank of filters, one per depth hypothesis of the class's
        ``depth_range_m`` (else the water the tables hold; `tracker.depth.bank.depth_hypotheses_m`),
        each with K at its depth; each cycle's row is that of the hypothesis of the largest
        posterior weight times the bearings' fit along its track, and ``depth_m`` and
        ``depth_sd_m`` the median and sd of the depth posterior from the levels of every band
        (``band`` given: its levels alone) along the tracks
        (`tracker.depth.bank.weigh_tracks`, taken every few cycles). Measured in
        docs/depth.md: 1.08x the position error of a filter given the true depth, where the
        filter with the depth as a state (retired: its own depth was confidently wrong) was at
        1.82x. ``DataFrame.attrs["depth"]`` holds each class's final
        posterior (`tracker.depth.bank.DepthChoice`). Needs levels (``rpf``, ``rpf-vp``).
        Otherwise the depth columns are blank here (``tracker.track.track`` fills in the depth
        the tables assume).
    integrate_errors : bool
        The level likelihood with the source level's and K's errors that last along the track
        integrated out (`tracker.levels.LevelErrors.of_tables`, each particle its own Kalman
        filter over them; the default); False: the paper's white likelihood with sigma_l.
    range_span_m : (float, float), optional
        Without ``config``: the prior range log-uniform between these two ranges, m; default
        `default_range_span_m` (1 km to the tables' reach). The paper's N(10 km, 2 km) is its
        scenario's prior, not a target's whose range nobody knows (docs/uncertainty.md).

    Returns
    -------
    pandas.DataFrame
        Columns ``tracker.trackfile.TRACK_COLUMNS``; absolute target position, its course and
        speed, sd of range, course and speed from the particles; ``tack`` is 1.

    Raises
    ------
    MeasurementFileError
        No level column for the band (rpf).
    GridFileError
        A class with source level model "p0" but no noise_mean_db.
    """
    import pandas as pd

    from acoustics.errors import GridFileError
    from envdata.classes import SourceLevelModel
    from tracker.depth.bank import depth_hypotheses_m, weigh_tracks
    from tracker.errors import MeasurementFileError
    from tracker.levels import LevelErrors, track_bearing_deg

    m = measurements
    chosen = method
    method = Method(chosen) if chosen in set(Method) else None
    if method is None or not method.is_particle_filter:
        raise MeasurementFileError(f"method {chosen!r} is not an RPF method (rpf, rpf-bot, rpf-vp)")
    spl = method is not Method.RPF_BOT
    if config is not None and range_span_m is not None:
        raise ValueError("give the range prior in config or as range_span_m, not both")
    cfg = config or command_config(tables, range_span_m, integrate_errors=integrate_errors)
    if method is Method.RPF_VP:
        cfg = replace(cfg, shrink=True)
    sig = np.asarray(m.bearing_sigma_deg, dtype=float)
    if sig.size and np.any(np.isfinite(sig)):  # the prior's bearing spread; each cycle its own sd
        cfg = replace(cfg, bearing_sigma_deg=float(np.nanmedian(sig)))
    levels = None
    bands = tables.band_names
    band_given = band is not None
    if spl:
        if band is None:
            usable = [b for b in bands if b in m.band_names]
            if not usable:
                raise MeasurementFileError(
                    f"{m.source}: method rpf needs a level column level_db_NAME for a band of "
                    f"the grid ({', '.join(bands)}); none found (method rpf-bot tracks on "
                    f"bearings only)")
            band = usable[0]
        if band not in m.band_names:
            raise MeasurementFileError(f"{m.source}: missing column 'level_db_{band}' needed by "
                                       f"method rpf for band {band!r}")
        levels = np.asarray(m.level_db[:, m.band_index(band)], dtype=float)
    bearings = np.radians(np.asarray(m.bearing_deg, dtype=float))
    first = int(np.flatnonzero(np.isfinite(bearings))[0])
    if first > 0:
        log.warning("%s: rows 1-%d have no bearing; the filter starts at row %d",
                    m.source, first, first + 1)
    n_nan_b = int(np.sum(~np.isfinite(bearings[first:])))
    if n_nan_b:
        log.warning("%s: %d rows without a bearing use %s", m.source, n_nan_b,
                    "the level alone" if levels is not None else "the prediction alone")
    if levels is not None and np.any(~np.isfinite(levels[first:])):
        log.warning("%s: %d rows without a level_db_%s use the bearing alone", m.source,
                    int(np.sum(~np.isfinite(levels[first:]))), band)
    rows = slice(first, None)
    t = np.asarray(m.t_s, dtype=float)[rows]
    vx, vy = m.obs_velocity_mps()
    obs = np.stack([m.obs_x_m, m.obs_y_m, vx, vy], axis=-1)[rows]
    depth = np.asarray(m.obs_depth_m, dtype=float)[rows]

    hypotheses = [cls_name] if cls_name is not None else list(tables.class_names)
    if method is Method.RPF_BOT:
        hypotheses = hypotheses[:1]  # bearings alone do not depend on the class
    away = tables.distance_from_origin_m(obs[:, 0], obs[:, 1])
    frames, choices = [], []
    for name in hypotheses:
        profiles = [None] * t.size
        model, p0, p0_sd, errors = SourceLevelModel.ROSS, math.nan, 0.0, None
        ic = tables.class_index(name)
        target = tables.classes[ic]
        if spl:
            ib = tables.band_index(band)
            model = target.source_level_model
            if target.source_level_model is SourceLevelModel.P0:
                if target.noise_mean_db is None:
                    raise GridFileError(f"{tables.source}: class {name!r} has source level "
                                        f"model {str(model)!r} but no noise_mean_db")
                p0, p0_sd = target.noise_mean_db, target.noise_sd_db
            if integrate_errors:
                errors = LevelErrors.of_tables(tables, ic, [ib], source_sd_db=target.noise_sd_db,
                                               bearing_deg=track_bearing_deg(np.degrees(bearings[rows])))
            if not depth_unknown:
                profiles = cycle_profiles(tables, ic, ib, depth, np.degrees(bearings[rows]), obs[:, 0], obs[:, 1])
        # the class hypothesis's own speed statistics as the speed prior; bearings alone without a
        # class, every class's speeds pooled (command_config)
        own_class = spl or cls_name is not None
        label = name if own_class else "any"
        cfg_class = replace(cfg, speed_mean_mps=target.speed_mean_mps, speed_sd_mps=target.speed_sd_mps) \
            if own_class else cfg

        def run(k_profiles, model=model, p0=p0, p0_sd=p0_sd, label=label, errors=errors, cfg=cfg_class):
            res = run_batch(t_s=t, obs_state=obs, bearing_rad_meas=bearings[rows][None],
                            level_db_meas=None if levels is None else levels[rows][None],
                            k_profiles=k_profiles, cfg=cfg, rng=rng, source_level_model=model,
                            p0_db=p0, p0_sd_db=p0_sd, summaries=True, level_errors=errors,
                            displacement_m=away, bearing_sd_rad=np.radians(sig[rows])[None] if sig.size else None)
            return _frame(res, t, obs, label, method.value)

        if depth_unknown:
            # a bank: one filter per depth hypothesis, each cycle the track of the hypothesis of
            # the largest weight times the bearings' fit (docs/depth.md)
            span = tables.target_depth_span_m(ic)
            z = depth_hypotheses_m(span, target.depth_m)
            tracks = [run(cycle_profiles(tables.at_target_depth(float(h)), ic, ib, depth, np.degrees(bearings[rows]),
                                         obs[:, 0], obs[:, 1])) for h in z]
            mm = m.take(np.arange(first, len(m)))
            frame, choice = weigh_tracks(tables, ic, mm.with_bands((band,)) if band_given else mm,
                                         tracks, z, span, rule="bearings")
            choices.append(choice)
        else:
            frame = run(profiles)
        frames.append(frame)
    out = pd.concat(frames, ignore_index=True)
    if depth_unknown:
        out.attrs["depth"] = choices
    return out


#: The near end of the command's range prior, m: a contact closer is not a motion analysis's.
NEAR_RANGE_M = 1000.0
#: The command's particles: with the range prior wide, 5000 leave the likelier paths too few.
COMMAND_PARTICLES = 20_000
#: The command's regularization kernel, a fraction of eqs. 27-28's bandwidth: on a wide cloud the
#: paper's h jitters every particle by a third of the cloud's spread at each resampling, which
#: carried the cloud away from paths whose levels fit far better (docs/uncertainty.md, "The
#: command's particle filters").
COMMAND_BANDWIDTH_SCALE = 0.25


def command_config(tables, range_span_m=None, *, integrate_errors: bool = True) -> RpfConfig:
    """The settings ``tmakit track --method rpf|rpf-bot|rpf-vp`` gives its filters: the range prior
    log-uniform over ``range_span_m`` (default `default_range_span_m`), `COMMAND_PARTICLES`
    particles sharing out three acceleration sds (`BEARINGS_ONLY_SIGMA_A_MIX_MPS2`: the
    measurements pick the motion model), `COMMAND_BANDWIDTH_SCALE` of the paper's bandwidth,
    sigma_l the level's own error where the errors that last are integrated out (else the
    paper's 10 dB), and the speed prior of every class of the grid pooled (mean and sd of their
    mixture; a class hypothesis takes its own). Measured on runs with BELLHOP's levels, tuned and
    held out: `bench.command_calibration`."""
    classes = tables.classes
    means = np.array([c.speed_mean_mps for c in classes], dtype=float)
    sds = np.array([c.speed_sd_mps for c in classes], dtype=float)
    pooled_mean = float(means.mean())
    pooled_sd = float(np.sqrt(np.mean(sds ** 2 + (means - pooled_mean) ** 2)))
    span = default_range_span_m(tables) if range_span_m is None else tuple(range_span_m)
    return RpfConfig(n_particles=COMMAND_PARTICLES, sigma_a_mix_mps2=BEARINGS_ONLY_SIGMA_A_MIX_MPS2,
                     bandwidth_scale=COMMAND_BANDWIDTH_SCALE, range_span_m=span,
                     speed_mean_mps=pooled_mean, speed_sd_mps=pooled_sd,
                     **({"level_sigma_db": MEASUREMENT_SD_DB} if integrate_errors else {}))


def default_range_span_m(tables) -> tuple[float, float]:
    """The command's range prior: log-uniform from `NEAR_RANGE_M` to the tables' last range
    (what they can say a level means), m."""
    far = float(tables.range_m[-1])
    return (min(NEAR_RANGE_M, 0.5 * far), far)


def _frame(res, t, obs, label: str, method: str):
    """A filter's run as track rows (absolute position, course, speed and their sds; one tack;
    the depth columns blank)."""
    import pandas as pd

    mean = res.mean[0]
    ax, ay = mean[:, 0] + obs[:, 0], mean[:, 1] + obs[:, 1]
    tvx, tvy = mean[:, 2] + obs[:, 2], mean[:, 3] + obs[:, 3]
    sds = res.extra["sd"][0]
    return pd.DataFrame({
        "t_s": t, "class": label, "x_m": ax, "y_m": ay, "range_m": np.hypot(mean[:, 0], mean[:, 1]),
        "bearing_deg": np.mod(np.degrees(bearing_rad(mean[:, 0], mean[:, 1])), 360.0),
        "course_deg": np.mod(np.degrees(np.arctan2(tvx, tvy)), 360.0),
        "speed_mps": np.hypot(tvx, tvy), "range_sd_m": sds[:, 0],
        "course_sd_deg": sds[:, 1], "speed_sd_mps": sds[:, 2], "tack": 1,
        "method": method, "depth_m": np.nan, "depth_sd_m": np.nan})


def cycle_profiles(tables, ic: int, ib: int, depth_m, bearing_deg, obs_x_m=None, obs_y_m=None) -> list:
    """The level model's K(r) of each cycle: from the tables where the observer is that cycle
    (an atlas's follow it; ``Tables.level_profiles_at``), at the cycle's observer depth, and for
    a grid with bearings at the cycle's measured bearing (between radials; a cycle without one
    takes the last bearing measured). The particles of a cycle lie within a few bearing sd of
    the measured bearing, where K changes little between radials tens of degrees apart.
    Observer positions default to the origin."""
    depth = np.asarray(depth_m, dtype=float)
    xs = np.zeros(depth.shape) if obs_x_m is None else np.asarray(obs_x_m, dtype=float)
    ys = np.zeros(depth.shape) if obs_y_m is None else np.asarray(obs_y_m, dtype=float)
    bearings = []
    last = None
    for b in np.asarray(bearing_deg, dtype=float):
        if np.isfinite(b):
            last = float(b)
        bearings.append(last)
    # the tables keep each profile: the same position, depth and bearing give the same one
    return tables.level_profiles_at(ic, ib, xs, ys, depth, bearings)
