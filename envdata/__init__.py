"""Sea areas: sound-speed profiles, bottom, ambient noise, sonar, bands and target classes;
bathymetry, climatology and casts sampled along radials for range- and bearing-dependent areas."""

from envdata.area import DEFAULT_AREA, Absorption, Area, GridSpec, Observer, Propagation, TlMode, Water
from envdata.areafile import area_from_json, area_path, area_to_json, builtin_area_names, load_area, parse_area
from envdata.bands import Band
from envdata.bottom import Bottom
from envdata.classes import SourceLevelModel, TargetClass, ross_source_level_db
from envdata.datafiles import BathymetrySource, ClimatologySource, DataFile, file_sha256
from envdata.errors import AreaError, InputError
from envdata.geometry import Bearings, Origin
from envdata.noise import Noise
from envdata.radials import Radial, area_radials, geodesic_points
from envdata.sonar import Sonar
from envdata.ssp import SoundSpeedProfile, TsProfile, munk_profile, munk_speed_mps, ts_profile

__all__ = [
    "DEFAULT_AREA", "Absorption", "Area", "AreaError", "Band", "BathymetrySource", "Bearings", "Bottom",
    "ClimatologySource", "DataFile", "GridSpec", "InputError", "Noise", "Observer", "Origin", "Propagation",
    "Radial", "Sonar", "SoundSpeedProfile", "SourceLevelModel", "TargetClass", "TlMode", "TsProfile", "Water",
    "area_from_json", "area_path", "area_radials", "area_to_json", "builtin_area_names", "file_sha256",
    "geodesic_points", "load_area", "munk_profile", "munk_speed_mps", "parse_area", "ross_source_level_db",
    "ts_profile",
]
