"""Sea areas: sound-speed profiles, bottom, ambient noise, sonar, bands and target classes;
bathymetry, climatology and casts sampled along radials for range- and bearing-dependent areas."""

from envdata.lazyexports import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(__name__, {
    "envdata.area": [
        "DEFAULT_AREA", "Absorption", "Area", "GridSpec", "Observer", "Propagation", "TlMode", "Water",
    ],
    "envdata.areafile": [
        "area_from_json", "area_path", "area_to_json", "builtin_area_names", "load_area", "parse_area",
    ],
    "envdata.bands": ["Band"],
    "envdata.bottom": ["Bottom"],
    "envdata.classes": ["SourceLevelModel", "TargetClass", "ross_source_level_db"],
    "envdata.datafiles": ["BathymetrySource", "ClimatologySource", "DataFile", "file_sha256"],
    "envdata.errors": ["AreaError", "InputError"],
    "envdata.geometry": ["Bearings", "Origin"],
    "envdata.noise": ["Noise"],
    "envdata.radials": ["Radial", "area_radials", "geodesic_points"],
    "envdata.sonar": ["Sonar"],
    "envdata.ssp": ["SoundSpeedProfile", "TsProfile", "munk_profile", "munk_speed_mps", "ts_profile"],
})
