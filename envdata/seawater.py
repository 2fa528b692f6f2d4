"""The kinds of temperature and salinity ocean products give, and TEOS-10 back to in-situ T and SP.

The World Ocean Atlas gives in-situ temperature and practical salinity, which is what tmakit's
sound speed (``envdata.ssp.teos10_speed_mps``) takes. Ocean reanalyses and models (Copernicus
Marine's GLORYS and MEDSEA, NEMO, CMIP) give potential temperature (``thetao``, CF
``sea_water_potential_temperature``), some Conservative Temperature (``bigthetao``,
``sea_water_conservative_temperature``) or Absolute Salinity (``absso``,
``sea_water_absolute_salinity``). `in_situ_ts` converts them with TEOS-10 (gsw) at each sample's
pressure (from its depth at its latitude) and position.
"""

from __future__ import annotations

from enum import StrEnum

import numpy as np


class TemperatureKind(StrEnum):
    IN_SITU = "in-situ"
    POTENTIAL = "potential"  # potential temperature referenced to 0 dbar
    CONSERVATIVE = "conservative"  # TEOS-10 Conservative Temperature


class SalinityKind(StrEnum):
    PRACTICAL = "practical"  # PSS-78
    ABSOLUTE = "absolute"  # TEOS-10 Absolute Salinity, g/kg


#: CF standard names of the kinds tmakit converts.
TEMPERATURE_STANDARD_NAMES = {"sea_water_temperature": TemperatureKind.IN_SITU,
                              "sea_water_potential_temperature": TemperatureKind.POTENTIAL,
                              "sea_water_conservative_temperature": TemperatureKind.CONSERVATIVE}
SALINITY_STANDARD_NAMES = {"sea_water_salinity": SalinityKind.PRACTICAL,
                           "sea_water_practical_salinity": SalinityKind.PRACTICAL,
                           "sea_water_absolute_salinity": SalinityKind.ABSOLUTE}


def in_situ_ts(temperature_c, salinity, depth_m, lat_deg, lon_deg, *, temperature_kind: TemperatureKind,
               salinity_kind: SalinityKind) -> tuple[np.ndarray, np.ndarray]:
    """In-situ temperature and practical salinity from the kinds a product gives.

    Parameters
    ----------
    temperature_c : array_like
        Temperature of ``temperature_kind``, degC.
    salinity : array_like
        Practical salinity, or Absolute Salinity (g/kg), by ``salinity_kind``.
    depth_m, lat_deg, lon_deg : array_like
        Depth (m, positive down) and position of each sample; all arguments broadcast.

    Returns
    -------
    temperature_c, salinity_psu : ndarray
        In-situ temperature, degC, and practical salinity; NaN where an input is NaN.

    Notes
    -----
    Pressure from depth at the latitude (``gsw.p_from_z``); SA from SP at the position
    (``gsw.SA_from_SP``) or SP from SA (``gsw.SP_from_SA``); CT from potential temperature
    (``gsw.CT_from_pt``); in-situ t from CT at the pressure (``gsw.t_from_CT``).
    """
    t = np.asarray(temperature_c, dtype=float)
    s = np.asarray(salinity, dtype=float)
    if temperature_kind == TemperatureKind.IN_SITU and salinity_kind == SalinityKind.PRACTICAL:
        return np.broadcast_arrays(t, s)[0].copy(), np.broadcast_arrays(t, s)[1].copy()
    import gsw

    p = gsw.p_from_z(-np.asarray(depth_m, dtype=float), lat_deg)
    if salinity_kind == SalinityKind.PRACTICAL:
        sp = s
        sa = gsw.SA_from_SP(s, p, lon_deg, lat_deg)
    else:
        sa = s
        sp = gsw.SP_from_SA(s, p, lon_deg, lat_deg)
    if temperature_kind == TemperatureKind.IN_SITU:
        t_out = t
    else:
        ct = gsw.CT_from_pt(sa, t) if temperature_kind == TemperatureKind.POTENTIAL else t
        t_out = gsw.t_from_CT(sa, ct, p)
    t_out, sp = np.broadcast_arrays(np.asarray(t_out, dtype=float), np.asarray(sp, dtype=float))
    return t_out.copy(), sp.copy()
