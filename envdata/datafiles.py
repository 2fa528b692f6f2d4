"""References from an area to its data files: bathymetry and climatology netCDF files.

An ``Area`` keeps where its data are, not the data: the path as the area file wrote it and the
folder of that area file, to resolve the path against when the data are read (by
``envdata.radials``). The folder is not part of equality, so an area read back from a grid's
``area_json`` (no folder, no files at hand) equals the area read from its file.
"""

from __future__ import annotations

import functools
import hashlib
from dataclasses import dataclass, field
from pathlib import Path

from envdata.errors import AreaError


@dataclass(frozen=True, slots=True, kw_only=True)
class DataFile:
    """A data file named by an area: ``path`` as written, resolved against ``folder``.

    ``folder`` is the folder of the area file (None: the current directory, e.g. for an area
    read back from ``area_json``); an absolute ``path`` is used as it is.
    """

    path: str
    folder: Path | None = field(default=None, compare=False)
    key: str = field(default="file", compare=False)  # the area-file key, for messages

    def __post_init__(self) -> None:
        if not isinstance(self.path, str) or not self.path.strip():
            raise AreaError(f"[water] {self.key}: must be a file name, got {self.path!r}")
        if "\x00" in self.path:
            raise AreaError(f"[water] {self.key}: file name contains a NUL character")

    def resolved(self) -> Path:
        """The path to read: ``path`` relative to the area file's folder."""
        p = Path(self.path).expanduser()
        if p.is_absolute() or self.folder is None:
            return p
        return Path(self.folder) / p


@dataclass(frozen=True, slots=True, kw_only=True)
class BathymetrySource:
    """A relief file in GEBCO's or EMODnet's layout: elevation(lat, lon), m, positive up
    (docs/formats.md "Bathymetry"); cells with no value (EMODnet's land) are land (``envdata.bathymetry``).

    ``variable`` names the elevation variable when it is not ``elevation`` or found by its CF
    standard_name (``bathymetry_variable`` in the area file).
    """

    file: DataFile
    variable: str | None = None

    def __post_init__(self) -> None:
        if self.variable is not None and (not isinstance(self.variable, str) or not self.variable):
            raise AreaError(f"[water] bathymetry_variable: must be a variable name, got {self.variable!r}")


@dataclass(frozen=True, slots=True, kw_only=True)
class ClimatologySource:
    """A climatology or reanalysis: temperature and salinity on (time, depth, lat, lon).

    Either one file holding both (``climatology``) or two, a temperature and a salinity file
    (``temperature`` and ``salinity``: WOA's own split, or a reanalysis' two downloads). ``month``
    picks the time steps of that month (``envdata.climatology``); a file with one time step is
    used as it is. ``temperature_variable`` and ``salinity_variable`` name the variables where
    their names and standard_names do not tell (the area file's keys of the same names).
    """

    file: DataFile | None = None
    temperature_file: DataFile | None = None
    salinity_file: DataFile | None = None
    month: int | None = None
    temperature_variable: str | None = None
    salinity_variable: str | None = None

    def __post_init__(self) -> None:
        split = (self.temperature_file is not None, self.salinity_file is not None)
        if self.file is not None and any(split):
            raise AreaError("[water] climatology: give either climatology or temperature and salinity, "
                            "not both")
        if self.file is None and not all(split):
            missing = "salinity" if split[0] else "temperature" if split[1] else "climatology"
            raise AreaError(f"[water] {missing}: missing; a climatology is one file (climatology) or "
                            f"WOA's two (temperature and salinity)")
        if self.month is not None and (isinstance(self.month, bool) or not isinstance(self.month, int)
                                       or not 1 <= self.month <= 12):
            raise AreaError(f"[water] month: must be an integer in 1..12, got {self.month!r}")
        for key in ("temperature_variable", "salinity_variable"):
            value = getattr(self, key)
            if value is not None and (not isinstance(value, str) or not value.strip()):
                raise AreaError(f"[water] {key}: must be a variable name, got {value!r}")

    @property
    def temperature(self) -> DataFile:
        """The file holding temperature (the one file, or WOA's temperature file)."""
        return self.file if self.file is not None else self.temperature_file

    @property
    def salinity(self) -> DataFile:
        """The file holding salinity (the one file, or WOA's salinity file)."""
        return self.file if self.file is not None else self.salinity_file

    def to_dict(self) -> dict[str, object]:
        """The ``[water]`` keys as they were given."""
        out: dict[str, object] = {}
        if self.file is not None:
            out["climatology"] = self.file.path
        else:
            out["temperature"] = self.temperature_file.path
            out["salinity"] = self.salinity_file.path
        if self.month is not None:
            out["month"] = self.month
        for key in ("temperature_variable", "salinity_variable"):
            if getattr(self, key) is not None:
                out[key] = getattr(self, key)
        return out


def file_sha256(path: str | Path) -> str:
    """Hex sha256 of a file's bytes, read in blocks (for the grid's record of its inputs)."""
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def area_data_files(water) -> dict[str, DataFile]:
    """The data files an area's water was read from, by role (bathymetry, climatology or
    temperature and salinity, cast)."""
    files: dict[str, DataFile] = {}
    if water.bathymetry is not None:
        files["bathymetry"] = water.bathymetry.file
    clim = water.climatology
    if clim is not None:
        if clim.file is not None:
            files["climatology"] = clim.file
        else:
            files["temperature"] = clim.temperature_file
            files["salinity"] = clim.salinity_file
    if water.cast is not None:
        files["cast"] = water.cast
    return files


def input_file_digests(water) -> dict[str, dict[str, str]]:
    """``{role: {"name": path as given, "sha256": ...}}`` of the data files behind an area's water.

    Raises
    ------
    AreaError
        A data file that is missing or not a regular file.
    """
    from envdata.files import check_input_file

    out = {}
    for role, data_file in area_data_files(water).items():
        path = check_input_file(data_file.resolved(), f"{role} file", AreaError)
        out[role] = {"name": data_file.path, "sha256": _cached_sha256(str(path), *_stamp(path))}
    return out


def _stamp(path: Path) -> tuple[int, int]:
    st = path.stat()
    return st.st_size, st.st_mtime_ns


@functools.lru_cache(maxsize=64)
def _cached_sha256(path: str, size: int, mtime_ns: int) -> str:
    return file_sha256(path)


def with_files_found(area, folders) -> object:
    """The area with each data file it names looked for in ``folders`` (in order) when it is not
    where its own folder says (an area read back from a grid's or an atlas's ``area_json`` names
    its files without a folder).

    Raises
    ------
    AreaError
        A file found nowhere, naming it and the folders looked in.
    """
    import dataclasses

    def found(data_file: DataFile | None) -> DataFile | None:
        if data_file is None or data_file.resolved().is_file():
            return data_file
        for folder in folders:
            if folder is not None and (Path(folder) / data_file.path).is_file():
                return dataclasses.replace(data_file, folder=Path(folder))
        looked = ", ".join(str(f) for f in folders if f is not None) or "nowhere else"
        raise AreaError(f"[water] {data_file.key}: {data_file.path!r} not found (looked as named and in {looked})")

    water = area.water
    changes = {}
    if water.bathymetry is not None:
        changes["bathymetry"] = dataclasses.replace(water.bathymetry, file=found(water.bathymetry.file))
    clim = water.climatology
    if clim is not None:
        changes["climatology"] = dataclasses.replace(clim, file=found(clim.file),
                                                     temperature_file=found(clim.temperature_file),
                                                     salinity_file=found(clim.salinity_file))
    if water.cast is not None:
        changes["cast"] = found(water.cast)
    return dataclasses.replace(area, water=dataclasses.replace(water, **changes))
