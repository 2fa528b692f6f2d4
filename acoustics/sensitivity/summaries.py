"""What a study says: bias, sd and constant-offset share of dK(r) = K_member(r) - K_nominal(r),
and the range error of level-based ranging (eq. 20) with the nominal tables in the member's sea.

Grinenkov & Mashoshin take dK as a constant offset, sd 1.5 dB surface / 2.0 dB submarine; the
summaries say how much of the measured dK is such an offset.

A study of an area with ``[origin]`` has a ``bearing`` axis: every summary over range is then
per bearing too, and ``k_rms_db(class, band, bearing, range)`` is what ``--into GRID`` writes
into a grid as its ``k_error_sd_db``, the sd the trackers take at each measurement's bearing and
range. Cells with no K (beyond land, a class deeper than the water) are left out of the means.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence

import numpy as np
import xarray as xr

from acoustics.detection import detection_terms, farthest_m
from acoustics.levelrange import level_range
from acoustics.sensitivity.face import Study
from envdata.errors import InputError

DEFAULT_EVAL_RANGES_M = (5000.0, 10000.0, 20000.0, 50000.0, 100000.0)


def level_range_m(k_levels_db: np.ndarray, k_table_db: np.ndarray, range_m: np.ndarray,
                  sigma_db: np.ndarray | None = None) -> np.ndarray:
    """Level-based range estimate, eq. 20: argmin_r sum_k (W_k - P0 - K_k(r) - H_k)^2 / sigma_k^2.

    Parameters
    ----------
    k_levels_db : ndarray, (..., band)
        Measured band levels minus P0 and H, i.e. the true K_k at the target's range, dB.
    k_table_db : ndarray, (band, range)
        The tables K_k(r) the ranging uses, dB.
    range_m : ndarray, (range,)
        Range axis of the tables, m.
    sigma_db : ndarray, (band,), optional
        Level error sd per band (eq. 11); equal weights by default.

    Returns
    -------
    range_m : ndarray, (...)
        The grid range minimising the weighted squared level misfit (all bands detected, I_k = 1).

    References
    ----------
    Grinenkov & Mashoshin (2024), eqs. 18-20.
    """
    levels = np.asarray(k_levels_db, dtype=float)
    table = np.asarray(k_table_db, dtype=float)
    flat = levels.reshape(-1, table.shape[0])
    sd = np.ones(table.shape[0]) if sigma_db is None else np.asarray(sigma_db, dtype=float)
    # the levels are already W - P0 - H: P0 = 0, H = 0, every band detected, no offsets
    r_opt, _ = level_range(flat, np.ones(flat.shape, dtype=bool), np.broadcast_to(sd, flat.shape),
                           np.zeros(len(flat)), table, np.asarray(range_m, dtype=float))
    return r_opt.reshape(levels.shape[:-1])


def summarize(study: Study, *, eval_ranges_m: Sequence[float] = DEFAULT_EVAL_RANGES_M,
              range_min_m: float | None = None, range_max_m: float | None = None) -> xr.Dataset:
    """Bias, sd, constant-offset share of dK(r) = K_member(r) - K_nominal(r), and the range error.

    Parameters
    ----------
    study : Study
        A study's face (``open_study``, or ``study_face`` of ``run_study``'s dataset).
    eval_ranges_m : sequence of float
        True ranges at which the implied range error of level-based ranging (eq. 20) is given.
    range_min_m, range_max_m : float, optional
        Range window of the scalar summaries (default: the whole range axis).

    Returns
    -------
    Dataset
        ``k_bias_db`` and ``k_sd_db`` (class, band, range); over the window, per (class, band):
        ``k_offset_sd_db`` (sd over members of each member's mean dK, the constant part),
        ``k_residual_rms_db`` (what a constant offset leaves), ``k_constant_fraction`` (share of
        the mean-square dK that is a constant offset), ``k_rms_error_db``; per class
        ``k_error_sd_db`` (rms dK over members, bands and ranges: the measured value for the
        area file); per (class, eval_range) ``range_bias_m``, ``range_rms_m`` and
        ``range_error_m(member, class, eval_range)``; ``k_offset_correlation(class, parameter)``
        says which drawn parameter moves the constant part.
    """
    ds = study.dataset
    rng = study.range_m
    lo = rng[0] if range_min_m is None else range_min_m
    hi = rng[-1] if range_max_m is None else range_max_m
    inside = (rng >= lo) & (rng <= hi)
    if not inside.any():
        raise InputError(f"range window [{lo:g}, {hi:g}] m contains no range of the study "
                         f"({rng[0]:g}-{rng[-1]:g} m)")
    dk = ds["k_db"] - ds["k_nominal_db"]
    n = ds.sizes["member"]
    radial = "bearing" in ds.dims
    bias = dk.mean("member")
    sd = dk.std("member", ddof=1) if n > 1 else xr.zeros_like(bias) * np.nan
    k_rms = np.sqrt((dk ** 2).mean("member"))
    win = dk.isel(range=inside)
    offset = win.mean("range", skipna=True)
    offset_sd = offset.std("member", ddof=1) if n > 1 else xr.zeros_like(offset.isel(member=0)) * np.nan
    ms = (win ** 2).mean(("member", "range"), skipna=True)
    residual = np.sqrt(((win - offset) ** 2).mean(("member", "range"), skipna=True))
    constant_fraction = xr.where(ms > 0, (offset ** 2).mean("member") / ms, 1.0)
    k_error = np.sqrt((win ** 2).mean([d for d in win.dims if d != "class"], skipna=True))

    eval_r = np.asarray([r for r in eval_ranges_m if rng[0] <= r <= rng[-1]], dtype=float)
    idx = np.abs(rng[None, :] - eval_r[:, None]).argmin(axis=1) if eval_r.size else np.zeros(0, int)
    true_r = rng[idx]
    err = _range_errors(study, idx, true_r)  # (member, class[, bearing], eval)
    # which drawn parameter drives the constant part: correlation over members of each parameter
    # with the member's offset (mean over bands, bearings and the window)
    params = list(study.parameters)
    band_offset = offset.mean([d for d in offset.dims if d not in ("member", "class")], skipna=True).values
    corr = np.full((ds.sizes["class"], len(params)), np.nan)
    for j, name in enumerate(params):
        x = study.parameters[name].astype(float)
        for ic in range(ds.sizes["class"]):
            y = band_offset[:, ic]
            if n > 2 and x.std() > 0 and y.std() > 0:
                corr[ic, j] = float(np.corrcoef(x, y)[0, 1])
    err_dims = ("member", "class", "bearing", "eval_range") if radial else ("member", "class", "eval_range")
    with np.errstate(invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a bearing with no K at a true range: NaN
        range_bias = np.nanmean(err, axis=0)
        range_rms = np.sqrt(np.nanmean(err ** 2, axis=0))
    det_dims = ("class", "band", "bearing") if radial else ("class", "band")
    detection = {}
    if study.area is not None:  # the detection rule needs the area's noise, sonar and levels
        det, det_nominal = _detection_ranges(study)
        detection = {
            "detection_range_m": (("member",) + det_dims, det,
                                  {"units": "m", "long_name": "largest range at which the band is detected at "
                                                              "the class's mean level, member's K"}),
            "detection_range_nominal_m": (det_dims, det_nominal, {"units": "m"}),
            "detection_range_sd_m": (det_dims, _nanstd_members(det) if n > 1
                                     else np.full(det_nominal.shape, np.nan),
                                     {"units": "m", "long_name": "sd over members of the detection range"})}
    out = xr.Dataset(
        {
            "k_offset_correlation": (("class", "parameter"), corr,
                                     {"units": "1", "long_name": "correlation over members of a perturbation "
                                                                 "parameter with the member's mean K offset"}),
            "k_bias_db": (bias.dims, bias.values, {"units": "dB", "long_name": "mean over members of K - K_nominal"}),
            "k_sd_db": (sd.dims, sd.values, {"units": "dB", "long_name": "sd over members of K - K_nominal"}),
            "k_rms_db": (k_rms.dims, k_rms.values,
                         {"units": "dB", "long_name": "rms over members of K - K_nominal: the K error sd at "
                                                      "each range (and bearing) that --into writes into a grid"}),
            "k_offset_sd_db": (offset_sd.dims, offset_sd.values,
                               {"units": "dB", "long_name": "sd over members of the range-mean of K - K_nominal"}),
            "k_residual_rms_db": (residual.dims, residual.values,
                                  {"units": "dB", "long_name": "rms of K - K_nominal after removing each "
                                                               "member's constant offset"}),
            "k_constant_fraction": (constant_fraction.dims, constant_fraction.values,
                                    {"units": "1", "long_name": "share of the mean-square K error that is a "
                                                                "constant offset per member"}),
            "k_rms_error_db": (ms.dims, np.sqrt(ms.values), {"units": "dB", "long_name": "rms of K - K_nominal"}),
            "k_error_sd_db": (k_error.dims, k_error.values,
                              {"units": "dB", "long_name": "measured sd of the transfer-characteristic error "
                                                           "(rms over members, bands, bearings and ranges)"}),
            "range_error_m": (err_dims, err,
                              {"units": "m", "long_name": "level-ranging (eq. 20) error with nominal tables"}),
            "range_bias_m": (err_dims[1:], range_bias, {"units": "m"}),
            "range_rms_m": (err_dims[1:], range_rms, {"units": "m"}),
            **detection,
        },
        coords={"member": ds["member"].values, "class": ds["class"].values, "band": ds["band"].values,
                "range": rng, "parameter": ("parameter", np.array(params, dtype=object)),
                "eval_range": ("eval_range", true_r, {"units": "m", "long_name": "true range"}),
                **({"bearing": study.bearing_deg} if radial else {})},
        attrs={"summary_range_min_m": float(lo), "summary_range_max_m": float(hi)})
    return out


def _nanstd_members(x: np.ndarray) -> np.ndarray:
    """sd over members (axis 0) of the finite values, NaN where fewer than two are finite."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return np.where(np.isfinite(x).sum(axis=0) > 1, np.nanstd(x, axis=0, ddof=1), np.nan)


def _range_errors(study: Study, idx: np.ndarray, true_r: np.ndarray) -> np.ndarray:
    """Error of level ranging (eq. 20) with the nominal tables in each member's sea, m:
    (member, class[, bearing], eval_range); NaN where the member has no K at the true range."""
    k_all, k_nom_all, rng = study.k_db, study.k_nominal_db, study.range_m
    radial = study.bearing_deg is not None
    n, n_class = study.members, len(study.class_names)
    n_bearing = study.bearing_deg.size if radial else 1
    est = np.full((n, n_class, n_bearing, idx.size), np.nan)
    for ic in range(n_class):
        for jb in range(n_bearing):
            k_member = (k_all[:, ic, :, jb] if radial else k_all[:, ic])[..., idx]   # (member, band, eval)
            k_nom = k_nom_all[ic, :, jb] if radial else k_nom_all[ic]             # (band, range)
            levels = np.moveaxis(k_member, 1, -1)                                 # (member, eval, band)
            have = np.isfinite(levels).all(axis=-1)
            if not np.isfinite(k_nom).any() or not have.any():
                continue
            r = level_range_m(np.where(have[..., None], levels, 0.0), k_nom, rng)
            est[:, ic, jb] = np.where(have, r, np.nan)
    err = est - true_r
    return err if radial else err[:, :, 0]


def _detection_ranges(study: Study) -> tuple[np.ndarray, np.ndarray]:
    """Detection range of each member and of the nominal tables at each class's mean level, m:
    (member, class, band[, bearing]) and (class, band[, bearing]); NaN where never detected."""
    area = study.area
    by_name = {c.name: c for c in area.classes}
    bands_by_name = {b.name: b for b in area.bands}
    bands = tuple(bands_by_name[b] for b in study.band_names)
    rng = study.range_m
    radial = study.bearing_deg is not None
    members, nominal = [], []
    for ic, name in enumerate(study.class_names):
        cls = by_name[name]
        terms = detection_terms(area, cls, bands)
        k = study.k_db[:, ic]          # (member, band[, bearing], range)
        k0 = study.k_nominal_db[ic]    # (band[, bearing], range)
        if radial:  # the band axis next to range for the rule, then back
            det = farthest_m(rng, terms.detected(np.moveaxis(k, 1, 2)))           # (member, bearing, band)
            det0 = farthest_m(rng, terms.detected(np.moveaxis(k0, 0, 1)))         # (bearing, band)
            members.append(np.moveaxis(det, 2, 1))
            nominal.append(det0.T)
        else:
            members.append(farthest_m(rng, terms.detected(k)))
            nominal.append(farthest_m(rng, terms.detected(k0)))
    return np.stack(members, axis=1), np.stack(nominal)


def k_error_by_class(summary: xr.Dataset) -> dict[str, float]:
    """The measured ``k_error_sd_db`` per class name, dB (what ``write_k_error`` writes back)."""
    return {str(c): float(v) for c, v in zip(summary["class"].values, summary["k_error_sd_db"].values)}
