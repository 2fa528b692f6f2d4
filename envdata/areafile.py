"""Area files: the TOML format of docs/formats.md, built-in areas, and the ``area_json`` of grids.

``parse_area`` turns a TOML document into a validated ``Area``; ``Area.to_dict`` is its inverse,
so ``area_from_json(area_to_json(area)) == area``. A grid's ``area_json`` is read back here,
validated exactly like an area file.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path
from typing import Any

from envdata.area import MUNK_TABLE_DEPTH_M, Absorption, Area, GridSpec, Observer, Propagation, TlMode, Water
from envdata.atlas import AtlasSpec
from envdata.bands import Band
from envdata.bottom import Bottom
from envdata.casts import read_cast
from envdata.classes import F_MINUS_2_DB_PER_OCTAVE, SourceLevelModel, TargetClass
from envdata.datafiles import BathymetrySource, ClimatologySource, DataFile
from envdata.errors import AreaError
from envdata.files import builtin_names, builtin_or_path
from envdata.geometry import Bearings, Origin
from envdata.names import check_name
from envdata.noise import Noise
from envdata.sonar import Sonar
from envdata.ssp import SoundSpeedProfile, TsProfile, munk_profile, ts_profile
from envdata.tomlfile import TomlTable, read_toml


def builtin_area_names() -> list[str]:
    return builtin_names("areas")


def area_path(name_or_path: str | Path) -> Path:
    """Resolve a built-in area name or a path to a TOML file."""
    return builtin_or_path(name_or_path, "areas", "area", AreaError)


def load_area(name_or_path: str | Path) -> Area:
    """Load a built-in area by name or an area TOML file; raises AreaError on bad input.

    Data files the area names (bathymetry, climatology) are resolved against the area file's
    folder when they are read; a cast is read now.
    """
    path = area_path(name_or_path)
    data, source = read_toml(path)
    return parse_area(data, source, folder=path.parent)


def parse_area(data: dict[str, Any], source: str = "<area>", folder: str | Path | None = None) -> Area:
    """Read an area-file document (a parsed TOML file, or a grid's ``area_json``) into an ``Area``.

    Parameters
    ----------
    data : dict
        The document.
    source : str
        Where it came from, to start every message with.
    folder : path-like, optional
        The area file's folder, against which its data-file paths are resolved when read. None
        (an ``area_json``): the paths are kept as written and no file is opened here.
    """
    folder = Path(folder) if folder is not None else None
    top = TomlTable(data, "top level", source)
    for key in ("area", "water", "bottom", "noise", "observer", "sonar", "bands", "classes", "grid"):
        top.value(key, required=True)
    for key in ("propagation", "origin", "bearings", "atlas"):
        top.value(key)
    top.done()

    origin = bearings = None
    if "origin" in data:
        t = TomlTable(data["origin"], "[origin]", source)
        origin = t.wrap(Origin, lat_deg=t.number("lat_deg"), lon_deg=t.number("lon_deg"))
        t.done()
    if "bearings" in data:
        t = TomlTable(data["bearings"], "[bearings]", source)
        listed = t.numbers("bearing_deg", required=False)
        bearings = t.wrap(Bearings, step_deg=t.number("step_deg", required=False),
                          listed_deg=tuple(listed) if listed is not None else None)
        t.done()

    t = TomlTable(data["area"], "[area]", source)
    name = check_name(t.string("name"), f"{source}: [area] name")
    description = t.string("description", "")
    # with an [origin], the area's position is the origin's
    latitude = t.number("latitude_deg", origin.lat_deg if origin else 45.0)
    longitude = t.number("longitude_deg", origin.lon_deg if origin else -30.0)
    if not -90.0 <= latitude <= 90.0:
        raise AreaError(f"{source}: [area] latitude_deg: must be in [-90, 90] deg, got {latitude}")
    t.done()

    t = TomlTable(data["water"], "[water]", source)
    water, cast_ts = _parse_water(t, source, folder, latitude, longitude)
    t.done()

    t = TomlTable(data["bottom"], "[bottom]", source)
    bottom = t.wrap(Bottom, speed_mps=t.number("speed_mps"), density_gcc=t.number("density_gcc"),
                    attenuation_db_per_wavelength=t.number("attenuation_db_per_wavelength", 0.0),
                    shear_speed_mps=t.number("shear_speed_mps", 0.0))
    t.done()

    noise = parse_noise(data["noise"], source)

    t = TomlTable(data["observer"], "[observer]", source)
    observer = Observer(depth_m=t.number("depth_m"))
    t.done()
    if cast_ts is not None and not cast_ts.bottom_m > observer.depth_m:
        raise AreaError(f"{source}: [water] cast: {water.cast.path!r} ends at {cast_ts.bottom_m:g} m and "
                        f"does not reach below the observer at {observer.depth_m:g} m")

    sonar = parse_sonar(data["sonar"], source)

    bands = []
    for i, item in enumerate(_array_of_tables(data["bands"], "[[bands]]", source)):
        t = TomlTable(item, f"[[bands]] #{i + 1}", source)
        bands.append(t.wrap(Band, name=t.string("name"), low_hz=t.number("low_hz"),
                            high_hz=t.number("high_hz")))
        t.done()

    classes = []
    for i, item in enumerate(_array_of_tables(data["classes"], "[[classes]]", source)):
        t = TomlTable(item, f"[[classes]] #{i + 1}", source)
        model = t.string("source_level_model", "p0", choices=tuple(m.value for m in SourceLevelModel))
        classes.append(t.wrap(
            TargetClass, name=t.string("name"), depth_m=t.number("depth_m"),
            speed_mean_mps=t.number("speed_mean_mps"), speed_sd_mps=t.number("speed_sd_mps"),
            noise_mean_db=t.number("noise_mean_db", required=model == "p0"),
            noise_sd_db=t.number("noise_sd_db", 0.0), k_error_sd_db=t.number("k_error_sd_db", 2.0),
            source_slope_db_per_octave=t.number("source_slope_db_per_octave", F_MINUS_2_DB_PER_OCTAVE),
            source_level_model=SourceLevelModel(model),
            depth_range_m=_depth_range(t.numbers("depth_range_m", required=False))))
        t.done()

    t = TomlTable(data["grid"], "[grid]", source)
    grid = t.wrap(GridSpec, range_max_m=t.number("range_max_m"), range_step_m=t.number("range_step_m"),
                  depth_step_m=t.number("depth_step_m"))
    t.done()

    defaults = Propagation()
    if "propagation" in data:
        t = TomlTable(data["propagation"], "[propagation]", source)
        propagation = t.wrap(
            Propagation,
            mode=TlMode(t.string("mode", defaults.mode.value, choices=tuple(m.value for m in TlMode))),
            beam_type=t.string("beam_type", defaults.beam_type),
            n_beams=t.integer("n_beams", defaults.n_beams),
            angle_min_deg=t.number("angle_min_deg", defaults.angle_min_deg),
            angle_max_deg=t.number("angle_max_deg", defaults.angle_max_deg),
            freqs_per_band=t.integer("freqs_per_band", defaults.freqs_per_band),
            frequency_shortcut=t.boolean("frequency_shortcut", defaults.frequency_shortcut),
            absorption=Absorption(t.string("absorption", defaults.absorption.value,
                                           choices=tuple(a.value for a in Absorption))),
            tl_max_db=t.number("tl_max_db", defaults.tl_max_db),
            run_timeout_s=t.number("run_timeout_s", required=False),
            step_m=t.number("step_m", required=False),
            surface_image_beams=t.integer("surface_image_beams", required=False),
            bottom_tolerance_m=t.number("bottom_tolerance_m", defaults.bottom_tolerance_m))
        t.done()
    else:
        propagation = defaults

    return _wrap_area(source, name=name, description=description, water=water, bottom=bottom,
                      noise=noise, observer=observer, sonar=sonar, bands=tuple(bands),
                      classes=tuple(classes), grid=grid, propagation=propagation,
                      latitude_deg=latitude, longitude_deg=longitude, origin=origin, bearings=bearings,
                      atlas=_parse_atlas(data["atlas"], source) if "atlas" in data else None)


def parse_noise(data: Any, source: str) -> Noise:
    """An area file's (or a receiver file's) ``[noise]`` table."""
    t = TomlTable(data, "[noise]", source)
    noise = t.wrap(Noise, spectrum_level_1khz_db=t.number("spectrum_level_1khz_db"),
                   slope_db_per_octave=t.number("slope_db_per_octave", -5.0))
    t.done()
    return noise


def parse_sonar(data: Any, source: str) -> Sonar:
    """An area file's (or a receiver file's) ``[sonar]`` table."""
    t = TomlTable(data, "[sonar]", source)
    sonar = t.wrap(Sonar, beamwidth_deg=t.number("beamwidth_deg"),
                   directivity_index_db=t.number("directivity_index_db"),
                   integration_time_s=t.number("integration_time_s"),
                   detection_threshold=t.number("detection_threshold"),
                   receiver_gain_db=t.number("receiver_gain_db", 0.0))
    t.done()
    return sonar


def _parse_atlas(data: Any, source: str) -> AtlasSpec:
    """The ``[atlas]`` table (envdata.atlas)."""
    t = TomlTable(data, "[atlas]", source)
    lat = t.numbers("lat_deg", required=False)
    lon = t.numbers("lon_deg", required=False)
    positions = t.value("positions")
    if positions is not None:
        if not isinstance(positions, list) or not positions:
            raise AreaError(f"{source}: [atlas] positions: must be a non-empty list of [lat_deg, lon_deg], "
                            f"got {positions!r:.80}")
        pairs = []
        for item in positions:
            if (not isinstance(item, list) or len(item) != 2
                    or any(isinstance(v, bool) or not isinstance(v, (int, float)) for v in item)):
                raise AreaError(f"{source}: [atlas] positions: each must be [lat_deg, lon_deg] (two numbers), "
                                f"got {item!r:.80}")
            pairs.append((float(item[0]), float(item[1])))
        positions = tuple(pairs)
    months = t.value("months")
    if months is not None:
        if not isinstance(months, list):
            raise AreaError(f"{source}: [atlas] months: must be a list of integers 1..12, got {months!r:.80}")
        months = tuple(months)
    depths = t.numbers("depth_m", required=False)
    spec = t.wrap(AtlasSpec, lat_deg=tuple(lat) if lat is not None else None,
                  lon_deg=tuple(lon) if lon is not None else None,
                  spacing_km=t.number("spacing_km", required=False), positions=positions, months=months,
                  depth_step_m=t.number("depth_step_m", required=False),
                  depth_m=tuple(depths) if depths is not None else None)
    t.done()
    return spec


#: The ways [water] gives the sound speed; exactly one is allowed.
_SOUND_SPEED_KEYS = {"ssp": ("ssp",), "a speed table": ("ssp_speed_mps",),
                     "a T/S table": ("temperature_c", "salinity_psu"), "a cast": ("cast",),
                     "a climatology": ("climatology", "temperature", "salinity")}


def _parse_water(t: TomlTable, source: str, folder: Path | None, latitude: float,
                 longitude: float) -> tuple[Water, TsProfile | None]:
    """The [water] table; also the cast's own T/S profile (to check it against the observer)."""
    if t.has("depth_m") and t.has("bathymetry"):
        raise AreaError(f"{source}: [water]: depth_m and bathymetry both given; give one (a flat bottom "
                        f"or a bathymetry file)")
    depth = bathymetry = None
    if t.has("bathymetry"):
        bathymetry = t.wrap(BathymetrySource,
                            file=t.wrap(DataFile, path=t.string("bathymetry"), folder=folder, key="bathymetry"),
                            variable=t.string("bathymetry_variable", required=False))
    else:
        if t.has("bathymetry_variable"):
            raise AreaError(f"{source}: [water] bathymetry_variable: only with a bathymetry file")
        depth = t.number("depth_m")
        if not depth > 0:
            raise AreaError(f"{source}: [water] depth_m: must be > 0 m, got {depth}")
    given = [label for label, keys in _SOUND_SPEED_KEYS.items() if any(t.has(k) for k in keys)]
    if len(given) > 1:
        raise AreaError(f"{source}: [water]: {' and '.join(given)} both give the sound speed; give one")
    for key in ("month", "temperature_variable", "salinity_variable"):
        if t.has(key) and given != ["a climatology"]:
            raise AreaError(f"{source}: [water] {key}: only with a climatology file (climatology, or "
                            f"temperature and salinity)")
    if given == ["a climatology"]:
        if t.has("ssp_interpolation"):
            raise AreaError(f"{source}: [water] ssp_interpolation: only for one profile, not with a "
                            f"climatology")
        files = {key: t.wrap(DataFile, path=t.string(key), folder=folder, key=key)
                 for key in ("climatology", "temperature", "salinity") if t.has(key)}
        climatology = t.wrap(ClimatologySource, file=files.get("climatology"),
                             temperature_file=files.get("temperature"), salinity_file=files.get("salinity"),
                             month=t.value("month"),
                             temperature_variable=t.string("temperature_variable", required=False),
                             salinity_variable=t.string("salinity_variable", required=False))
        return t.wrap(Water, depth_m=depth, bathymetry=bathymetry, climatology=climatology), None

    interpolation = t.string("ssp_interpolation", "C", choices=("C", "S", "N", "P"))
    ssp = ts = cast = cast_ts = None
    if t.has("ssp"):
        t.string("ssp", choices=("munk",))  # the one named profile
        ssp = t.wrap(munk_profile, depth if depth is not None else MUNK_TABLE_DEPTH_M)
        ssp = dataclasses.replace(ssp, interpolation=interpolation)
    elif t.has("cast"):
        cast = t.wrap(DataFile, path=t.string("cast"), folder=folder, key="cast")
        try:
            cast_ts = read_cast(cast.resolved(), latitude_deg=latitude)
        except AreaError as exc:
            raise AreaError(f"{source}: [water] cast: {exc}") from None
        ts = dataclasses.replace(cast_ts, interpolation=interpolation)
    elif t.has("temperature_c") or t.has("salinity_psu"):
        z = t.numbers("ssp_depth_m")
        temp = t.numbers("temperature_c")
        sal = t.numbers("salinity_psu")
        _check_depths(z, source)
        if depth is not None:
            ssp = t.wrap(ts_profile, z, temp, sal, latitude_deg=latitude, longitude_deg=longitude)
            ssp = t.wrap(dataclasses.replace, ssp, interpolation=interpolation)
        else:
            ts = t.wrap(TsProfile, depth_m=tuple(z), temperature_c=tuple(temp), salinity_psu=tuple(sal),
                        interpolation=interpolation)
    else:
        z = t.numbers("ssp_depth_m")
        c = t.numbers("ssp_speed_mps")
        _check_depths(z, source)
        ssp = t.wrap(SoundSpeedProfile, depth_m=tuple(z), speed_mps=tuple(c), interpolation=interpolation)
    if ts is not None and depth is not None:  # a flat bottom: the cast to the bottom, as speeds
        cut = ts.cut_at(depth)
        ssp = t.wrap(ts_profile, cut.depth_m, cut.temperature_c, cut.salinity_psu, latitude_deg=latitude,
                     longitude_deg=longitude)
        ssp = dataclasses.replace(ssp, interpolation=interpolation, kind="cast")
        ts = None
    return t.wrap(Water, depth_m=depth, ssp=ssp, ts=ts, bathymetry=bathymetry, cast=cast), cast_ts


def _wrap_area(source: str, **kwargs) -> Area:
    try:
        return Area(**kwargs)
    except AreaError as exc:
        raise AreaError(f"{source}: {exc}") from None


def _array_of_tables(value: Any, where: str, source: str) -> list:
    if not isinstance(value, list) or not value:
        raise AreaError(f"{source}: {where}: need at least one entry (an array of tables)")
    return value


def _check_depths(z: list[float], source: str) -> None:
    if any(v < 0 for v in z):
        raise AreaError(f"{source}: [water] ssp_depth_m: depths must be >= 0 m, "
                        f"got {min(z)} m")


def area_to_json(area: Area) -> str:
    """The area as the JSON text grids store in their ``area_json`` attribute."""
    return json.dumps(area.to_dict(), sort_keys=True)


def area_from_json(text: str, source: str = "<grid>") -> Area:
    """Read an ``area_json`` text back into an ``Area``, validated exactly like an area file.

    Raises
    ------
    AreaError
        Not JSON, not an object, or an area the TOML loader would refuse; the message names
        ``source`` and ``area_json``.
    """
    where = f"{source}: area_json"
    if not isinstance(text, str):
        raise AreaError(f"{where}: must be a string of JSON, got {type(text).__name__}")
    try:
        data = json.loads(text)
    except (ValueError, RecursionError) as exc:
        raise AreaError(f"{where}: not valid JSON ({exc})") from None
    if not isinstance(data, dict):
        raise AreaError(f"{where}: must be a JSON object, got {type(data).__name__}")
    return parse_area(data, where)


def _depth_range(values: list[float] | None) -> tuple[float, ...] | None:
    """A class's ``depth_range_m`` as given (the class checks it is [min, max])."""
    return None if values is None else tuple(values)
