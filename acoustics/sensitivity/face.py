"""The face of a sensitivity study, like the grid's (``acoustics.grid.face``): what its readers ask.

A study dataset (``acoustics.sensitivity.study.study_dataset``, docs/formats.md "Sensitivity
study file") comes in through `study_face` (``open_study`` for a file, ``run_study_file`` for a
study just run): its variables are checked once, K is taken in one order (member, class, band
[, bearing], range), the area it stores is read back once, and the summaries, the plots, the K
error written into a grid and the studies that draw a member's sea ask the face, not the dataset.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
import xarray as xr

from envdata.area import Area
from envdata.areafile import area_from_json
from envdata.errors import AreaError, InputError


class StudyFileError(InputError):
    """A study file that is missing, not netCDF, or lacks what a study file holds (docs/formats.md)."""


REQUIRED_STUDY_VARS = {"k_db": ("member", "class", "band", "range"), "k_nominal_db": ("class", "band", "range")}
#: A study of an area with [origin] has a bearing axis.
REQUIRED_RADIAL_STUDY_VARS = {"k_db": ("member", "class", "band", "bearing", "range"),
                              "k_nominal_db": ("class", "band", "bearing", "range")}


@dataclass(frozen=True, eq=False, kw_only=True)
class Study:
    """A sensitivity study: every member's K(r) and the nominal one, with what was drawn.

    Attributes
    ----------
    source : str
        The study's name in messages (its file, else its area).
    dataset : xr.Dataset
        The checked study dataset (for the summaries' labelled arithmetic).
    area : Area or None
        The area stored in the study (None in a study written without it).
    class_names, band_names : tuple of str
    range_m : ndarray, shape (R,)
    bearing_deg : ndarray, shape (N,), or None
        The radials of a bearing-dependent study; None without bearings.
    k_db : ndarray, shape (E, C, M, [N,] R)
        K(r) of each member, dB.
    k_nominal_db : ndarray, shape (C, M, [N,] R)
        K(r) of the nominal area, dB.
    parameters : dict of str to ndarray (E,)
        Each perturbation parameter drawn, per member.
    depth_m : ndarray, shape (D,), or None
        The TL depth axis of a study run with TL (``--tl``); None without.
    tl_db : ndarray, shape (E, C, M, [N,] D, R), or None
        Band TL of each member, dB; None without.
    """

    source: str
    dataset: xr.Dataset = field(repr=False)
    area: Area | None
    class_names: tuple[str, ...]
    band_names: tuple[str, ...]
    range_m: np.ndarray
    bearing_deg: np.ndarray | None
    k_db: np.ndarray
    k_nominal_db: np.ndarray
    parameters: dict[str, np.ndarray]
    depth_m: np.ndarray | None = None
    tl_db: np.ndarray | None = None

    @property
    def members(self) -> int:
        return int(self.k_db.shape[0])

    @property
    def name(self) -> str:
        """The study's area name, for titles."""
        return str(self.dataset.attrs.get("area", "?"))

    @property
    def source_hash(self) -> str:
        return str(self.dataset.attrs.get("source_hash", "?"))

    def member_k_db(self, member: int) -> np.ndarray:
        """K(r) of one member, (C, M, [N,] R), dB."""
        return self.k_db[int(member)]

    def radial_index(self, bearing_deg: float) -> int:
        """The radial nearest to a bearing (across 0/360 deg)."""
        return int(np.argmin(np.abs((self.bearing_deg - bearing_deg + 180.0) % 360.0 - 180.0)))

    def along(self, j: int) -> Study:
        """The study along radial ``j`` alone, as a study without bearings (its title says which)."""
        ds = self.dataset.isel(bearing=j)
        ds.attrs = {**self.dataset.attrs, "area": f"{self.name}, bearing {float(self.bearing_deg[j]):g} deg"}
        return replace(self, dataset=ds, bearing_deg=None, k_db=self.k_db[..., j, :],
                       k_nominal_db=self.k_nominal_db[..., j, :],
                       tl_db=None if self.tl_db is None else self.tl_db[:, :, :, j])


def study_face(ds: xr.Dataset, source: str | None = None) -> Study:
    """The face of a study dataset, its variables checked (`StudyFileError` naming what is missing)."""
    source = source or str(ds.encoding.get("source") or ds.attrs.get("area", "<study>"))
    radial = "bearing" in ds.dims
    for name, dims in (REQUIRED_RADIAL_STUDY_VARS if radial else REQUIRED_STUDY_VARS).items():
        if name not in ds or ds[name].dims != dims:
            raise StudyFileError(f"{source}: missing variable {name}{dims}")
    area = None
    if "area_json" in ds.attrs:
        try:
            area = area_from_json(ds.attrs["area_json"], f"{source}: the study's area_json")
        except AreaError as exc:
            raise StudyFileError(str(exc)) from None
    params = {name: np.asarray(coord.values) for name, coord in ds.coords.items()
              if coord.dims == ("member",) and name != "member"}
    return Study(source=source, dataset=ds, area=area, class_names=tuple(str(c) for c in ds["class"].values),
                 band_names=tuple(str(b) for b in ds["band"].values), range_m=np.asarray(ds["range"].values),
                 bearing_deg=np.asarray(ds["bearing"].values, dtype=float) if radial else None,
                 k_db=ds["k_db"].values, k_nominal_db=ds["k_nominal_db"].values, parameters=params,
                 depth_m=np.asarray(ds["depth"].values) if "tl_db" in ds else None,
                 tl_db=ds["tl_db"].values if "tl_db" in ds else None)


__all__ = ["Study", "StudyFileError", "study_face"]
