"""Ocean reanalyses (Copernicus Marine GLORYS/MEDSEA, HYCOM): names, kinds, TEOS-10 to in-situ T, time steps."""

from __future__ import annotations

import datetime

import gsw
import numpy as np
import pytest
import xarray as xr
from numpy.testing import assert_allclose

import envdata
from envdata.climatology import open_climatology
from envdata.datafiles import ClimatologySource, DataFile
from envdata.radials import area_radials, geodesic_points
from envdata.seawater import SalinityKind, TemperatureKind, in_situ_ts
from tests.conftest import DATA
from tests.envdata.conftest import make_area, write_dtm
from tests.fixtures.reanalyses import GLORYS_LEVELS_M, monthly_times, write_cmems, write_hycom

LAT = 42.5 + np.arange(13) / 12.0  # GLORYS's 1/12-deg centres
LON = 4.5 + np.arange(13) / 12.0
LEVELS = GLORYS_LEVELS_M[:38]  # to 1452 m
AUGUST = [datetime.datetime(2022, 8, 16, 12)]


def theta(z, y, x):
    """Potential temperature, degC: a warm mixed layer over 13 degC deep water; land north-east."""
    t = 13.0 + 10.0 * np.exp(-z / 40.0) + 0.0 * y * x
    return np.where((y > 43.4) & (x > 5.4), np.nan, t)


def practical(z, y, x):
    s = 38.0 + 0.5 * (1.0 - np.exp(-z / 300.0)) + 0.0 * y * x
    return np.where((y > 43.4) & (x > 5.4), np.nan, s)


def cube(field, steps: int = 1, offsets=None) -> np.ndarray:
    z, y, x = np.meshgrid(LEVELS, LAT, LON, indexing="ij")
    offsets = offsets if offsets is not None else [0.0] * steps
    return np.stack([field(z, y, x) + dv for dv in offsets])


def one(path, month=None, **names) -> ClimatologySource:
    return ClimatologySource(file=DataFile(path=str(path)), month=month, **names)


def split(t_path, s_path, month=None) -> ClimatologySource:
    return ClimatologySource(temperature_file=DataFile(path=str(t_path)),
                             salinity_file=DataFile(path=str(s_path)), month=month)


def centre_column(field, lat=43.0, lon=5.0):
    i = int(np.argmin(np.abs(field.lat_deg - lat)))
    j = int(np.argmin(np.abs(field.lon_deg - lon)))
    return field.lat_deg[i], field.lon_deg[j], field.temperature_c[:, i, j], field.salinity_psu[:, i, j]


@pytest.mark.parametrize("packed", [False, True])
def test_glorys_potential_temperature_becomes_in_situ_by_teos10(tmp_path, packed):
    path = write_cmems(tmp_path / "glorys.nc", AUGUST, LEVELS, LAT, LON, title="test GLORYS12",
                       temperature=cube(theta), salinity=cube(practical), packed=packed)
    with open_climatology(one(path)) as clim:
        assert clim.temperature.name == "thetao" and clim.salinity.name == "so"
        assert clim.temperature_kind == TemperatureKind.POTENTIAL and clim.salinity_kind == SalinityKind.PRACTICAL
        field = clim.load_box([43.0], [5.0])
    lat, lon, t, sp = centre_column(field)
    z = field.depth_m
    pt = theta(z, lat, lon)
    atol = 1e-5 if not packed else 4e-4  # float32, or int16 steps of 0.00073
    assert_allclose(sp, practical(z, lat, lon), rtol=0, atol=atol)
    # back from the in-situ temperature read to the potential temperature written (gsw.pt_from_t)
    p = gsw.p_from_z(-z, lat)
    sa = gsw.SA_from_SP(sp, p, lon, lat)
    assert_allclose(gsw.pt_from_t(sa, t, p, 0.0), pt, rtol=0, atol=atol + 1e-6)
    # adiabatic warming: none at the surface, ~0.2 degC at 1450 m in 13 degC water
    assert abs(t[0] - pt[0]) < 1e-3
    assert 0.15 < t[-1] - pt[-1] < 0.25


def test_conservative_temperature_absolute_salinity_and_kelvin(tmp_path):
    ct = cube(theta)
    sa = cube(lambda z, y, x: practical(z, y, x) * 35.16504 / 35.0)
    path = write_cmems(tmp_path / "teos.nc", AUGUST, LEVELS, LAT, LON, title="test TEOS-10 variables",
                       temperature=ct, salinity=sa, temperature_kind="conservative", salinity_kind="absolute")
    with open_climatology(one(path)) as clim:
        assert (clim.temperature.name, clim.salinity.name) == ("bigthetao", "absso")
        assert clim.temperature_kind == TemperatureKind.CONSERVATIVE and clim.salinity_kind == SalinityKind.ABSOLUTE
        field = clim.load_box([43.0], [5.0])
    lat, lon, t, sp = centre_column(field)
    z = field.depth_m
    p = gsw.p_from_z(-z, lat)
    sa_back = gsw.SA_from_SP(sp, p, lon, lat)
    assert_allclose(sa_back, practical(z, lat, lon) * 35.16504 / 35.0, rtol=0, atol=1e-5)
    assert_allclose(gsw.CT_from_t(sa_back, t, p), theta(z, lat, lon), rtol=0, atol=1e-5)
    # in-situ temperature in kelvin (standard_name sea_water_temperature): minus 273.15
    kelvin = write_cmems(tmp_path / "kelvin.nc", AUGUST, LEVELS, LAT, LON, title="test kelvin",
                         temperature=cube(theta) + 273.15, salinity=cube(practical), temperature_kind="in-situ",
                         temperature_units="K")
    with open_climatology(one(kelvin)) as clim:
        assert clim.temperature_kind == TemperatureKind.IN_SITU
        _, _, t_k, _ = centre_column(clim.load_box([43.0], [5.0]))
    assert_allclose(t_k, theta(z, lat, lon), rtol=0, atol=2e-5)  # float32 kelvin


def test_kind_is_told_by_standard_name_else_name_else_long_name(tmp_path):
    values = {"temperature": cube(theta), "salinity": cube(practical)}
    # no standard_names: thetao and votemper are potential temperature by their names
    for name in ("thetao", "votemper"):
        path = write_cmems(tmp_path / f"{name}.nc", AUGUST, LEVELS, LAT, LON, title="t", names={"temperature": name},
                           standard_names=False, **values)
        with open_climatology(one(path)) as clim:
            assert clim.temperature.name == name and clim.temperature_kind == TemperatureKind.POTENTIAL
    # a name nobody uses, found by its standard_name alone
    path = write_cmems(tmp_path / "odd.nc", AUGUST, LEVELS, LAT, LON, title="t",
                       names={"temperature": "TEMPERATURE_POT", "salinity": "PSAL"}, **values)
    with open_climatology(one(path)) as clim:
        assert (clim.temperature.name, clim.salinity.name) == ("TEMPERATURE_POT", "PSAL")
        assert clim.temperature_kind == TemperatureKind.POTENTIAL
    # "temp" without a standard_name: the long_name tells (ROMS writes "potential temperature")
    with xr.open_dataset(path) as ds:
        roms = ds.rename({"TEMPERATURE_POT": "temp", "PSAL": "salt"}).load()
    del roms["temp"].attrs["standard_name"], roms["salt"].attrs["standard_name"]
    roms["temp"].attrs["long_name"] = "time-averaged potential temperature"
    roms.to_netcdf(tmp_path / "roms.nc")
    with open_climatology(one(tmp_path / "roms.nc")) as clim:
        assert clim.temperature_kind == TemperatureKind.POTENTIAL and clim.salinity_kind == SalinityKind.PRACTICAL
    roms["temp"].attrs["long_name"] = "temperature"  # nothing tells: in-situ, as WOA
    roms.to_netcdf(tmp_path / "plain.nc")
    with open_climatology(one(tmp_path / "plain.nc")) as clim:
        assert clim.temperature_kind == TemperatureKind.IN_SITU


def test_medsea_split_datasets_and_hycom_in_situ_packed_on_0_360(tmp_path):
    t_path = write_cmems(tmp_path / "med-tem.nc", AUGUST, LEVELS, LAT, LON, title="test MEDSEA tem",
                         temperature=cube(theta))
    s_path = write_cmems(tmp_path / "med-sal.nc", AUGUST, LEVELS, LAT, LON, title="test MEDSEA sal",
                         salinity=cube(practical))
    with open_climatology(split(t_path, s_path)) as clim:
        med = clim.load_box([43.0], [5.0])
    with open_climatology(one(write_cmems(tmp_path / "both.nc", AUGUST, LEVELS, LAT, LON, title="t",
                                          temperature=cube(theta), salinity=cube(practical)))) as clim:
        both = clim.load_box([43.0], [5.0])
    assert_allclose(med.temperature_c, both.temperature_c, equal_nan=True)
    # HYCOM: in-situ water_temp as it is (int16 steps of 0.001)
    hycom = write_hycom(tmp_path / "hycom.nc", AUGUST, LEVELS, LAT, np.mod(LON, 360.0), title="test HYCOM",
                        temperature=cube(theta), salinity=cube(practical))
    with open_climatology(one(hycom)) as clim:
        assert (clim.temperature.name, clim.salinity.name) == ("water_temp", "salinity")
        assert clim.temperature_kind == TemperatureKind.IN_SITU
        lat, lon, t, s = centre_column(clim.load_box([43.0], [5.0]))
    assert_allclose(t, theta(LEVELS, lat, lon), rtol=0, atol=6e-4)
    assert_allclose(s, practical(LEVELS, lat, lon), rtol=0, atol=6e-4)


def test_time_steps_are_picked_by_calendar_month(tmp_path):
    # twelve monthly means from June 2022: index month - 1 would be wrong, the calendar is right
    times = monthly_times(datetime.date(2022, 6, 1), 12)
    offsets = [float(k) for k in range(12)]  # step k is warmer by k degC
    path = write_cmems(tmp_path / "year.nc", times, LEVELS, LAT, LON, title="t",
                       temperature=cube(theta, offsets=offsets), salinity=cube(practical, offsets=[0.0] * 12))
    with open_climatology(one(path, month=8)) as clim:  # August 2022 is step 2
        _, _, aug, _ = centre_column(clim.load_box([43.0], [5.0]))
    with open_climatology(one(write_cmems(tmp_path / "aug.nc", AUGUST, LEVELS, LAT, LON, title="t",
                                          temperature=cube(theta, offsets=[2.0]),
                                          salinity=cube(practical)))) as clim:
        _, _, expected, _ = centre_column(clim.load_box([43.0], [5.0]))
    assert_allclose(aug, expected, rtol=0, atol=1e-6)
    # daily fields: the steps of the month are averaged
    days = [datetime.datetime(2022, 8, d, 12) for d in (29, 30, 31)] + [datetime.datetime(2022, 9, 1, 12)]
    path = write_cmems(tmp_path / "days.nc", days, LEVELS, LAT, LON, title="t",
                       temperature=cube(theta, offsets=[0.0, 1.0, 2.0, 9.0]),
                       salinity=cube(practical, offsets=[0.0] * 4))
    with open_climatology(one(path, month=8)) as clim:
        _, _, mean, _ = centre_column(clim.load_box([43.0], [5.0]))
    with open_climatology(one(write_cmems(tmp_path / "mid.nc", AUGUST, LEVELS, LAT, LON, title="t",
                                          temperature=cube(theta, offsets=[1.0]),
                                          salinity=cube(practical)))) as clim:
        _, _, middle, _ = centre_column(clim.load_box([43.0], [5.0]))
    assert_allclose(mean, middle, rtol=0, atol=1e-5)
    with pytest.raises(envdata.AreaError, match=r"days\.nc: 'thetao' has 4 time steps \(months 8, 9\); give "
                                                r"\[water\] month = 1\.\.12 \(the steps in that month are averaged\)$"):
        open_climatology(one(path))
    with pytest.raises(envdata.AreaError, match=r"days\.nc: 'thetao' has no time step in month 7 \(its 4 steps "
                                                r"are in months 8, 9\)$"):
        open_climatology(one(path, month=7))


def test_variables_named_in_the_area_and_ambiguous_files(tmp_path):
    path = write_cmems(tmp_path / "two.nc", AUGUST, LEVELS, LAT, LON, title="t", names={"temperature": "pt_a"},
                       temperature=cube(theta), salinity=cube(practical))
    with xr.open_dataset(path) as ds:
        both = ds.assign(pt_b=ds.pt_a + 1.0).load()
    both["pt_b"].attrs = dict(both["pt_a"].attrs)
    both.to_netcdf(tmp_path / "ambiguous.nc")
    with pytest.raises(envdata.AreaError, match=r"ambiguous\.nc: several variables could be the temperature "
                                                r"\(pt_a, pt_b, by standard_name sea_water_potential_temperature\); "
                                                r"name one with \[water\] temperature_variable$"):
        open_climatology(one(tmp_path / "ambiguous.nc"))
    with open_climatology(one(tmp_path / "ambiguous.nc", temperature_variable="pt_b")) as clim:
        assert clim.temperature.name == "pt_b" and clim.temperature_kind == TemperatureKind.POTENTIAL
    with pytest.raises(envdata.AreaError, match=r"ambiguous\.nc: no variable 'pt_c' \(the temperature, \[water\] "
                                                r"temperature_variable\); the file has pt_a, pt_b, so$"):
        open_climatology(one(tmp_path / "ambiguous.nc", temperature_variable="pt_c"))
    with pytest.raises(envdata.AreaError, match=r"ambiguous\.nc: variable 'so' \(the temperature\) has "
                                                r"standard_name 'sea_water_salinity'; need one of"):
        open_climatology(one(tmp_path / "ambiguous.nc", temperature_variable="so"))


def test_in_situ_ts_leaves_in_situ_and_practical_as_they_are():
    t, s = in_situ_ts([14.0, 13.0], [38.0, 38.5], [0.0, 1000.0], 43.0, 5.0, temperature_kind=TemperatureKind.IN_SITU,
                      salinity_kind=SalinityKind.PRACTICAL)
    assert t.tolist() == [14.0, 13.0] and s.tolist() == [38.0, 38.5]
    t, s = in_situ_ts(np.nan, 38.0, 1000.0, 43.0, 5.0, temperature_kind=TemperatureKind.POTENTIAL,
                      salinity_kind=SalinityKind.PRACTICAL)
    assert np.isnan(t) and s == 38.0


def test_an_area_on_emodnet_and_glorys_gives_teos10_speeds_of_in_situ_temperature(tmp_path):
    def dtm(lat, lon):
        e = -1000.0 + 10000.0 * (lat - 43.0) + 0.0 * lon
        return np.where(e >= -30.0, np.nan, e)

    write_dtm(tmp_path / "dtm.nc", dtm, box=(42.7, 43.3, 4.7, 5.3))
    times = monthly_times(datetime.date(2022, 1, 1), 12)
    write_cmems(tmp_path / "glorys.nc", times, LEVELS, LAT, LON, title="t", temperature=cube(theta, 12),
                salinity=cube(practical, 12))
    area = make_area({"bathymetry": "dtm.nc", "climatology": "glorys.nc", "month": 8}, folder=tmp_path,
                     range_max_m=12000.0, bearings={"bearing_deg": [0.0, 180.0]})
    north, south = area_radials(area)
    assert north.land_range_m is not None and 10000.0 < north.land_range_m < 11000.0
    z = south.ssp_depth_m
    lat, lon = geodesic_points(43.0, 5.0, 180.0, south.ssp_range_m)
    levels = np.isin(z, LEVELS.astype(np.float32).astype(float))
    assert levels.sum() == LEVELS.size
    for j in range(south.ssp_range_m.size):
        p = gsw.p_from_z(-z[levels], lat[j])
        sp = practical(z[levels], 0.0, 0.0)
        sa = gsw.SA_from_SP(sp, p, lon[j], lat[j])
        t = gsw.t_from_CT(sa, gsw.CT_from_pt(sa, theta(z[levels], 0.0, 0.0)), p)
        # the reader converts at the cell centres: across cells only the position in SA differs
        expected = gsw.sound_speed(sa, gsw.CT_from_t(sa, t, p), p)
        assert_allclose(south.speed_mps[levels, j], expected, rtol=0, atol=0.01)
    # read as if in-situ, the deep water would be ~0.2 degC colder: ~0.7 m/s slower at 1450 m
    deep = np.flatnonzero(levels)[-1]
    p = gsw.p_from_z(-z[deep], 43.0)
    sa = gsw.SA_from_SP(practical(z[deep], 0, 0), p, 5.0, 43.0)
    naive = gsw.sound_speed(sa, gsw.CT_from_t(sa, theta(z[deep], 0, 0), p), p)
    assert south.speed_mps[deep, 0] - naive > 0.5


def test_an_area_file_names_medsea_split_files_and_their_variables(tmp_path):
    write_dtm(tmp_path / "dtm.nc", lambda lat, lon: -1500.0 + 0.0 * lat * lon, box=(42.7, 43.3, 4.7, 5.3))
    write_cmems(tmp_path / "med-tem.nc", AUGUST, LEVELS, LAT, LON, title="t", temperature=cube(theta),
                names={"temperature": "T_POT"}, standard_names=False)
    write_cmems(tmp_path / "med-sal.nc", AUGUST, LEVELS, LAT, LON, title="t", salinity=cube(practical))
    text = (DATA / "tiny-munk.toml").read_text()
    water = ('[water]\nbathymetry = "dtm.nc"\ntemperature = "med-tem.nc"\nsalinity = "med-sal.nc"\n'
             'temperature_variable = "T_POT"\n')
    start = text.index("[water]")
    end = text.index("\n[", start + 1) + 1
    text = text[:start] + water + "\n" + text[end:]
    text += '\n[origin]\nlat_deg = 43.0\nlon_deg = 5.0\n\n[bearings]\nbearing_deg = [90.0]\n'
    (tmp_path / "med.toml").write_text(text)
    area = envdata.load_area(tmp_path / "med.toml")
    assert area.water.climatology.temperature_variable == "T_POT"
    (radial,) = area_radials(area)
    # "T_POT" has no standard_name and a name nobody uses: read as in-situ, as given (the long_name
    # "Temperature" does not say potential), so the speed is TEOS-10 of theta as in-situ
    z = radial.ssp_depth_m
    k = int(np.argmin(np.abs(z - LEVELS[20])))
    p = gsw.p_from_z(-z[k], radial.lat_deg[0])
    sa = gsw.SA_from_SP(practical(z[k], 0, 0), p, 5.0, 43.0)
    expected = gsw.sound_speed(sa, gsw.CT_from_t(sa, theta(z[k], 0, 0), p), p)
    assert radial.speed_mps[k, 0] == pytest.approx(float(expected), abs=0.01)
