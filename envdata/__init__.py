"""Sea areas: sound-speed profiles, bottom, ambient noise, sonar, bands and target classes."""

from envdata.area import DEFAULT_AREA, Absorption, Area, GridSpec, Observer, Propagation, TlMode, Water
from envdata.areafile import (area_from_json, area_path, area_to_json, builtin_area_names, load_area,
                              parse_area)
from envdata.bands import Band
from envdata.bottom import Bottom
from envdata.classes import SourceLevelModel, TargetClass, ross_source_level_db
from envdata.errors import AreaError, InputError
from envdata.noise import Noise
from envdata.sonar import Sonar
from envdata.ssp import SoundSpeedProfile, munk_profile, munk_speed_mps, ts_profile

__all__ = [
    "DEFAULT_AREA", "Absorption", "Area", "AreaError", "Band", "Bottom", "GridSpec", "InputError",
    "Noise", "Observer", "Propagation", "Sonar", "SoundSpeedProfile", "SourceLevelModel",
    "TargetClass", "TlMode", "Water", "area_from_json", "area_path", "area_to_json", "builtin_area_names", "load_area",
    "munk_profile", "munk_speed_mps", "parse_area", "ross_source_level_db", "ts_profile",
]
