"""The grid dataset (docs/formats.md "Grid file"): its coordinates, variables and attributes, CF-1.8.

``flat_dataset`` makes the grid of an area without ``[origin]`` (``tl_db(class, band, depth,
range)`` from the class's depth); ``radial_dataset`` the bearing-dependent one (a built grid's, an
atlas's table at one position) from the same coordinates and attributes (``grid_coords``,
``grid_attrs``); ``with_k_error_model`` writes K's error model a study measured into a grid
(``tmakit sensitivity --into``), ``with_k_error_sd`` the format-2 map of one sd by range.
"""

from __future__ import annotations

import json
from datetime import datetime, timezone

import numpy as np
import xarray as xr

from acoustics.grid.formats import GRID_FORMAT
from acoustics.version import TMAKIT_VERSION
from envdata.area import Area
from envdata.areafile import area_to_json


def now_iso() -> str:
    """The current UTC time, ISO 8601 to the second."""
    return datetime.now(timezone.utc).replace(microsecond=0).isoformat().replace("+00:00", "Z")


def grid_coords(area: Area, depth_m: np.ndarray, range_m: np.ndarray) -> dict:
    """The coordinates every grid has: class, band, depth, range and the band and class figures."""
    bands = area.bands
    return {
        "class": ("class", np.array([c.name for c in area.classes], dtype=object),
                  {"long_name": "target class hypothesis"}),
        "band": ("band", np.array([b.name for b in bands], dtype=object), {"long_name": "frequency band"}),
        "depth": ("depth", depth_m, {"units": "m", "standard_name": "depth", "positive": "down",
                                     "axis": "Z", "long_name": "receiver depth"}),
        "range": ("range", range_m, {"units": "m", "long_name": "horizontal range from the source"}),
        "band_low_hz": ("band", np.array([b.low_hz for b in bands]),
                        {"units": "Hz", "long_name": "lower band edge"}),
        "band_high_hz": ("band", np.array([b.high_hz for b in bands]),
                         {"units": "Hz", "long_name": "upper band edge"}),
        "band_center_hz": ("band", np.array([b.center_hz for b in bands]),
                           {"units": "Hz", "long_name": "band centre (geometric mean of the edges)"}),
        "source_depth_m": ("class", np.array([c.depth_m for c in area.classes]),
                           {"units": "m", "long_name": "radiating depth of the class", "positive": "down"}),
    }


def grid_attrs(area: Area, model: str, digest: str, exe_info: dict | None, *,
               water_depth_m: float, ssp_interpolation: str) -> dict:
    """The global attributes every grid has (docs/formats.md "Grid without bearings")."""
    attrs = {
        "Conventions": "CF-1.8",
        "tmakit_format": GRID_FORMAT,
        "title": f"tmakit propagation grid for area {area.name}",
        "institution": "tmakit",
        "source": f"tmakit {TMAKIT_VERSION}, model {model}",
        "history": f"{now_iso()} created by tmakit grids build",
        "references": "Grinenkov & Mashoshin (2024) eqs. 12-13; Porter, The BELLHOP manual (2011)",
        "comment": "dB quantities carry units 'dB' with their reference in the 'reference' attribute",
        "area": area.name,
        "area_description": area.description,
        "model": str(model),
        "observer_depth_m": float(area.observer.depth_m),
        "water_depth_m": float(water_depth_m),
        "created": now_iso(),
        "source_hash": digest,
        "area_json": area_to_json(area),
    }
    if exe_info is not None:
        prop = area.propagation
        attrs["bellhop_version"] = exe_info["version"]
        attrs["bellhop_sha256"] = exe_info["sha256"]
        settings = {
            "mode": str(prop.mode), "beam_type": prop.beam_type, "n_beams": prop.n_beams,
            "angle_min_deg": prop.angle_min_deg, "angle_max_deg": prop.angle_max_deg,
            "absorption": str(prop.absorption), "freqs_per_band": prop.freqs_per_band,
            "frequency_shortcut": prop.frequency_shortcut, "tl_max_db": prop.tl_max_db,
            "ssp_interpolation": ssp_interpolation}
        if prop.step_m is not None:
            settings["step_m"] = prop.step_m
        if prop.bottom_tolerance_m > 0.0:
            settings["bottom_tolerance_m"] = prop.bottom_tolerance_m
        if str(prop.mode) == "semicoherent":  # the surface's arrivals run of a table from the observer
            settings["surface_image_beams"] = prop.image_beams
        attrs["bellhop_settings"] = json.dumps(settings, sort_keys=True)
    return attrs


def flat_dataset(area, model, depth, rng, tl, k, k_urick, beta, digest, exe_info, *,
                 tl_obs=None) -> xr.Dataset:
    """The grid of an area without ``[origin]``: TL from the class's depth (``fixed_end = "source"``)
    and, when given, ``tl_obs_db``: TL from the observer's depth (``fixed_end = "observer"``)."""
    prop = area.propagation
    dims4 = ("class", "band", "depth", "range")
    dims3 = ("class", "band", "range")
    data_vars = {
        "tl_db": (dims4, tl, {"units": "dB", "long_name": "band transmission loss",
                              "reference": "1 m from the source", "fixed_end": "source",
                              "comment": "intensity average over the band weighted by the class spectrum; "
                                         f"shadows capped at {prop.tl_max_db:g} dB"}),
        "k_db": (dims3, k, {"units": "dB", "long_name": "transfer characteristic K(r) at the observer depth",
                            "reference": "band level W = P0 + K(r) + H (Grinenkov & Mashoshin eq. 12)",
                            "model": str(model)}),
        "k_urick_db": (dims3, k_urick, {"units": "dB",
                                        "long_name": "transfer characteristic K(r), Urick approximate formula",
                                        "reference": "Grinenkov & Mashoshin eq. 13 with A = 1"}),
        "anomaly_db": (dims3, k - k_urick, {"units": "dB",
                                            "long_name": "propagation anomaly 10 lg A implied by the model",
                                            "reference": "K(r) minus the Urick K(r) with A = 1"}),
        "beta_db_per_km": (("band",), beta, {"units": "dB km-1",
                                             "long_name": "volume attenuation at the band centre"}),
    }
    if tl_obs is not None:
        data_vars["tl_obs_db"] = (dims4, tl_obs, {
            "units": "dB", "long_name": "band transmission loss from a source at the observer depth",
            "reference": "1 m from the source", "fixed_end": "observer",
            "comment": "by reciprocity the loss from a target at depth to the observer (K at any "
                       "target depth); the class spectrum weights the band as in tl_db; shadows "
                       f"capped at {prop.tl_max_db:g} dB"})
    attrs = grid_attrs(area, model, digest, exe_info, water_depth_m=area.water.depth_m,
                       ssp_interpolation=area.water.ssp.interpolation)
    return xr.Dataset(data_vars, coords=grid_coords(area, depth, rng), attrs=attrs)


def radial_dataset(area: Area, model: str, digest: str, exe_info: dict | None, *, bearing_deg, depth_m, range_m,
                   tl_db, k_db, k_urick_db, bottom_depth_m, beta_db_per_km, ray_step_m: float | None = None,
                   input_files: dict | None = None) -> xr.Dataset:
    """The grid of an area with ``[origin]``: TL between the observer at the origin and a point at
    depth along each radial (``fixed_end = "observer"``, docs/formats.md "Grid with bearings").

    ``tl_db`` is (class, band, bearing, depth, range), ``k_db`` (class, band, bearing, range),
    ``k_urick_db`` (class, band, range), ``bottom_depth_m`` (bearing, range); ``ray_step_m`` and
    ``input_files`` (the data files' digests) are recorded when given.
    """
    coords = grid_coords(area, depth_m, range_m)
    coords["bearing"] = ("bearing", bearing_deg, {"units": "degree", "long_name": "bearing from the origin, "
                                                                                  "clockwise from true north"})
    coords["range"] = ("range", range_m, {"units": "m", "long_name": "range from the origin along the "
                                                                     "radial (geodesic)"})
    coords["depth"] = ("depth", depth_m, {"units": "m", "standard_name": "depth", "positive": "down", "axis": "Z",
                                          "long_name": "depth of the point the observer looks at"})
    dims4 = ("class", "band", "bearing", "range")
    data_vars = {
        "tl_db": (("class", "band", "bearing", "depth", "range"), tl_db, {
            "units": "dB", "long_name": "band transmission loss between the observer and a point at depth",
            "reference": "1 m from the source", "fixed_end": "observer",
            "comment": "BELLHOP from the observer at the origin (reciprocity); intensity average over the band "
                       "weighted by the class spectrum; shadows capped at "
                       f"{area.propagation.tl_max_db:g} dB; NaN below the bottom and beyond land"}),
        "k_db": (dims4, k_db, {"units": "dB", "long_name": "transfer characteristic K(r) of a target of the "
                                                          "class along the bearing",
                               "reference": "band level W = P0 + K(r) + H (Grinenkov & Mashoshin eq. 12)",
                               "model": str(model)}),
        "k_urick_db": (("class", "band", "range"), k_urick_db, {
            "units": "dB", "long_name": "transfer characteristic K(r), Urick approximate formula",
            "reference": "Grinenkov & Mashoshin eq. 13 with A = 1"}),
        "anomaly_db": (dims4, k_db - k_urick_db[:, :, None, :], {
            "units": "dB", "long_name": "propagation anomaly 10 lg A implied by the model",
            "reference": "K(r) minus the Urick K(r) with A = 1"}),
        "bottom_depth_m": (("bearing", "range"), bottom_depth_m, {
            "units": "m", "long_name": "water depth along the radial", "positive": "down",
            "comment": "bathymetry sampled bilinearly along WGS84 geodesics; NaN beyond land"}),
        "beta_db_per_km": (("band",), beta_db_per_km, {"units": "dB km-1",
                                                       "long_name": "volume attenuation at the band centre"}),
    }
    attrs = grid_attrs(area, model, digest, exe_info, water_depth_m=float(depth_m[-1]), ssp_interpolation="Q")
    attrs.update({
        "title": f"tmakit bearing-dependent propagation grid for area {area.name}",
        "origin_lat_deg": float(area.origin.lat_deg), "origin_lon_deg": float(area.origin.lon_deg),
        "radials": "WGS84 geodesics from the origin (pyproj); bathymetry and climatology sampled "
                   "bilinearly; sound speed by TEOS-10 (gsw)"})
    if ray_step_m is not None:
        attrs["ray_step_m"] = float(ray_step_m)
    if input_files is not None:
        attrs["input_files"] = json.dumps(input_files, sort_keys=True)
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def with_k_error_sd(ds: xr.Dataset, sd_db: np.ndarray, comment: str, source: str = "<grid>") -> xr.Dataset:
    """A grid dataset with ``k_error_sd_db`` set (replaced if there), shaped like ``k_db``.

    Parameters
    ----------
    ds : xr.Dataset
        The grid (``Tables.dataset``).
    sd_db : ndarray
        (class, band, range), or (class, band, bearing, range) with bearings, in the grid's
        order; dB, >= 0, NaN unknown.
    comment : str
        Where the values come from (a study's file and source_hash), for the attribute.
    source : str
        The grid's name in messages.

    Raises
    ------
    GridFileError
        ``sd_db`` not of K's shape.
    """
    from acoustics.errors import GridFileError

    canonical = ("class", "band", "bearing", "range") if "bearing" in ds.dims else ("class", "band", "range")
    sd = np.asarray(sd_db, dtype=float)
    shape = tuple(ds.sizes[d] for d in canonical)
    if sd.shape != shape:
        raise GridFileError(f"{source}: k_error_sd_db of shape {sd.shape} does not fit the grid's K {shape}")
    dims = ds["k_db"].dims
    return ds.assign(k_error_sd_db=(dims, np.transpose(sd, [canonical.index(d) for d in dims]), {
        "units": "dB", "long_name": "sd of the transfer-characteristic error K - K_true",
        "comment": f"{comment}; NaN where unknown: the class's k_error_sd_db serves there"}))


def with_k_error_model(ds: xr.Dataset, model: xr.Dataset, comment: str, source: str = "<grid>") -> xr.Dataset:
    """A grid dataset with K's error model (``acoustics.grid.kerror.MODEL_VARS``) set from
    ``model`` (`acoustics.sensitivity.errormodel.k_error_model`, on the grid's classes, bands and
    bearings), replacing a model or a format-2 ``k_error_sd_db`` map already there.

    Raises
    ------
    GridFileError
        ``model`` not on the grid's class, band (and bearing) coordinates.
    """
    from acoustics.errors import GridFileError
    from acoustics.grid.kerror import MODEL_VARS

    radial = "bearing" in ds.dims
    out = ds.drop_vars([n for n in ("k_error_sd_db", *MODEL_VARS) if n in ds.data_vars])
    for name, dims in MODEL_VARS.items():
        want = dims[radial]
        var = model[name]
        for d in want:
            if d not in var.dims or not np.array_equal(np.asarray(var[d].values), np.asarray(ds[d].values)):
                raise GridFileError(f"{source}: the K error model's {name} is not on the grid's {d} axis")
        out = out.assign({name: (want, np.asarray(var.transpose(*want).values, dtype=float),
                                 {**var.attrs, "comment": comment})})
    return out.assign_attrs(tmakit_format=GRID_FORMAT)
