"""A grid dataset checked against the grid contract and turned into its face.

``acoustics.open_tables`` reads a grid file, or takes a dataset in memory, through
`checked_tables`; an atlas's table of one position and month (``AtlasStore.sel``) too. A grid of
an older format is read through its upgrade step or refused (``acoustics.grid.formats``), then
every dimension, variable, attribute and the stored area are checked
(``acoustics.grid.schema.check_grid``), and the face the dataset's shape calls for is returned:
the one place outside which nothing asks a grid its shape.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from acoustics.errors import GridFileError
from acoustics.grid.face import Tables
from acoustics.grid.flattables import FlatTables
from acoustics.grid.formats import upgrade_grid
from acoustics.grid.kerror import MODEL_VARS, MeasuredKError
from acoustics.grid.radialtables import RadialTables
from acoustics.grid.schema import check_grid
from envdata.area import Area


def checked_tables(ds: xr.Dataset, source: str | None = None, *, area: Area | None = None) -> Tables:
    """The face of a grid dataset, checked against the grid contract.

    Parameters
    ----------
    ds : xr.Dataset
    source : str, optional
        The grid's name in messages (default: its file, else its area).
    area : Area, optional
        The area the dataset was made from in this process (an atlas's table): its
        ``area_json`` is then not parsed again, only checked against the coordinates.

    Raises
    ------
    GridFileError
        Naming the grid and what is wrong with it.
    """
    source = source or str(ds.encoding.get("source") or ds.attrs.get("area", "<grid>"))
    ds = upgrade_grid(ds, source, GridFileError)
    area = check_grid(ds, source, area=area)
    by_class = {c.name: c for c in area.classes}
    by_band = {b.name: b for b in area.bands}
    common = dict(source=source, area=area, dataset=ds,
                  classes=tuple(by_class[str(n)] for n in ds["class"].values),
                  bands=tuple(by_band[str(n)] for n in ds["band"].values),
                  range_m=np.asarray(ds["range"].values, dtype=float),
                  depth_m=np.asarray(ds["depth"].values, dtype=float),
                  observer_depth_m=float(np.asarray(ds.attrs["observer_depth_m"]).item()))
    dims = ("class", "band", "bearing", "range") if "bearing" in ds.dims else ("class", "band", "range")
    if "k_error_sd_db" in ds.data_vars:
        common["k_error_sd_grid_db"] = _values(ds, "k_error_sd_db", *dims)
    if all(name in ds.data_vars for name in MODEL_VARS):
        radial = "bearing" in ds.dims
        common["k_error_measured"] = MeasuredKError(
            offset_sd_db=_values(ds, "k_offset_sd_db", *MODEL_VARS["k_offset_sd_db"][radial]),
            residual_sd_db=_values(ds, "k_residual_sd_db", *MODEL_VARS["k_residual_sd_db"][radial]),
            residual_length_m=_values(ds, "k_residual_length_m", "class"),
            band_correlation=_values(ds, "k_offset_band_correlation", "class"),
            bearing_deg=np.asarray(ds["bearing"].values, dtype=float) if radial else None,
            fallback_offset_db=np.array([c.k_error_sd_db for c in common["classes"]], dtype=float),
            source=str(ds["k_offset_sd_db"].attrs.get("comment", "a sensitivity study")))
    if "bearing" not in ds.dims:
        return FlatTables(k_grid_db=_values(ds, "k_db", "class", "band", "range"),
                          tl_db=_values(ds, "tl_db", "class", "band", "depth", "range"),
                          tl_obs_db=(_values(ds, "tl_obs_db", "class", "band", "depth", "range")
                                     if "tl_obs_db" in ds.data_vars else None), **common)
    return RadialTables(
        k_grid_db=_values(ds, "k_db", "class", "band", "bearing", "range"),
        tl_db=_values(ds, "tl_db", "class", "band", "bearing", "depth", "range"),
        bearing_deg=np.asarray(ds["bearing"].values, dtype=float),
        bottom_depth_m=_values(ds, "bottom_depth_m", "bearing", "range"),
        origin_lat_deg=float(np.asarray(ds.attrs["origin_lat_deg"]).item()),
        origin_lon_deg=float(np.asarray(ds.attrs["origin_lon_deg"]).item()), **common)


def _values(ds: xr.Dataset, name: str, *dims: str) -> np.ndarray:
    return np.asarray(ds[name].transpose(*dims).values, dtype=float)


__all__ = ["checked_tables"]
