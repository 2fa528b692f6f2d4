"""Drawing perturbations (`acoustics.sensitivity.perturbspec`) and applying them to an Area.

A perturbation names what is uncertain and how much (a standard deviation). Each ensemble
member draws its own standard-normal numbers from ``np.random.default_rng([seed, member])``
and makes a perturbed ``Area`` with ``dataclasses.replace``. Every draw is truncated: at +-4 sd,
and at the physical range of what it changes (a bottom attenuation below 0, a class below the
bottom, a temperature below freezing, a profile folded by a displacement): a draw that makes
the area invalid is redrawn, so a member never fails half-way through a study and draws far
from a limit are the plain normal ones. `check_perturbations` refuses, before any work, a spec
whose truncation would swallow its distribution (fewer than `MIN_VALID_FRACTION` of a normal's
draws within +-4 sd give a valid area, e.g. sd 20 km/s on a 1600 m/s bottom).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from acoustics.sensitivity.perturbspec import FIELD_KINDS, Kind, Perturbation, PerturbationError, check_kind_fits
from envdata.area import Area, Observer, Water
from envdata.climatology import open_climatology
from envdata.errors import AreaError
from envdata.fieldchange import FieldChange, ReliefChange, SmoothField, WaterChange
from envdata.ssp import MAX_SPEED_MPS, MIN_SPEED_MPS, SoundSpeedProfile, speed_outside

TRUNCATE_SD = 4.0  # draws beyond +-4 sd are redrawn
MIN_VALID_FRACTION = 0.25  # a spec must give a valid area for this much of a normal's mass in +-4 sd
MAX_REDRAWS = 10_000  # redraws of one perturbation of one member before the member is given up
ISOTHERMAL_GRADIENT_PER_S = 0.0163  # dc/dz of isothermal, isohaline sea water (pressure term), 1/s
REFERENCE_SALINITY_PSU = 35.0  # salinity assumed when a profile's temperature is inferred from its speed


def check_perturbations(area: Area, perturbations: list[Perturbation]) -> None:
    """Raise PerturbationError unless every spec gives ``area`` a valid member often enough.

    Each spec is applied to the nominal area on a grid of draws over +-4 sd (for EOF modes, all
    modes alike and alternating in sign); the normal's mass on the valid draws must be at
    least `MIN_VALID_FRACTION`. The error names the draw nearest to 0 that fails, and why.
    """
    seen: dict[Kind, str] = {}
    for p in perturbations:
        if p.kind in seen:
            raise PerturbationError(f"{p.source}: perturbation {p.kind} given twice "
                                    f"(also in {seen[p.kind]})")
        seen[p.kind] = p.source
        check_kind_fits(area, p)
    _check_field_data(area, [p for p in perturbations if p.kind in FIELD_KINDS])
    grid = np.linspace(-TRUNCATE_SD, TRUNCATE_SD, 161)
    weights = np.exp(-0.5 * grid ** 2)
    for p in perturbations:
        if p.kind in FIELD_KINDS:  # changes of the data files, valid by construction (clipped)
            continue
        patterns = [np.ones(p.n_draws)]
        if p.n_draws > 1:
            patterns.append((-1.0) ** np.arange(p.n_draws))
        for pattern in patterns:
            failures = {}
            for x in grid:
                reason = _invalid_reason(area, p, x * pattern)
                if reason is not None:
                    failures[float(x)] = reason
            valid = np.array([float(x) not in failures for x in grid])
            fraction = float(weights[valid].sum() / weights.sum())
            if fraction < MIN_VALID_FRACTION:
                x = min(failures, key=abs)
                raise PerturbationError(
                    f"{p.source}: perturbation {p.describe()}: only {100 * fraction:.0f} % of its draws "
                    f"within +-{TRUNCATE_SD:g} sd give a valid area (need {100 * MIN_VALID_FRACTION:.0f} %); "
                    f"lower the sd (at {x:+.2f} sd: {failures[x]})")


def _invalid_reason(area: Area, p: Perturbation, xi: np.ndarray) -> str | None:
    """Why ``xi`` makes ``area`` invalid under ``p`` (without the spec's own prefix), or None."""
    try:
        _apply_one(area, p, xi)
    except (AreaError, PerturbationError) as exc:
        text = str(exc)
        prefix = f"{p.source}: perturbation {p.describe()}: "
        return text[len(prefix):] if text.startswith(prefix) else text
    return None


def draw(perturbations: list[Perturbation], rng: np.random.Generator) -> list[np.ndarray]:
    """Standard-normal numbers for each perturbation (in application order), truncated at +-4."""
    out = []
    for p in _ordered(perturbations):
        xi = rng.standard_normal(p.n_draws)
        while np.any(np.abs(xi) > TRUNCATE_SD):
            bad = np.abs(xi) > TRUNCATE_SD
            xi[bad] = rng.standard_normal(int(bad.sum()))
        out.append(xi)
    return out


def _check_field_data(area: Area, perturbations: list[Perturbation]) -> None:
    """The climatology has what the water and month kinds need: sds to scale by, other months."""
    need_sd = [p for p in perturbations if p.kind is Kind.WATER
               and (math.isnan(p.option("sd_c")) or math.isnan(p.option("sd_psu")))]
    months = [p for p in perturbations if p.kind is Kind.MONTH]
    if not (need_sd or months):
        return
    with open_climatology(area.water.climatology) as clim:
        if need_sd and not clim.has_sd:
            p = need_sd[0]
            raise PerturbationError(f"{p.source}: perturbation water: the climatology {clim.describe()} has no "
                                    f"standard deviations (t_sd, s_sd); give sd_c and sd_psu")
        if months and not clim.has_months:
            p = months[0]
            raise PerturbationError(f"{p.source}: perturbation month: the climatology {clim.describe()} holds "
                                    f"one month; the month kind needs a file of 12 months ([water] month "
                                    f"picking one)")
    source = area.water.climatology
    for p in months:  # the months a member may mix in must be in the files
        offset = p.option("offset_months")
        steps = [-1, 1] if math.isnan(offset) else [int(math.copysign(1, offset)) if abs(offset) <= 1 else int(offset)]
        for step in steps:
            other = (source.month - 1 + step) % 12 + 1
            try:
                open_climatology(dataclasses.replace(source, month=other)).close()
            except AreaError as exc:
                raise PerturbationError(f"{p.source}: perturbation month: month {other} is needed: {exc}") from None


def perturb_area(area: Area, perturbations: list[Perturbation],
                 rng: np.random.Generator) -> tuple[Area, dict[str, float]]:
    """One ensemble member of a flat area: the perturbed area and the drawn parameters (name ->
    value, units in name); `perturb_environment` for every area."""
    area, _, params = perturb_environment(area, perturbations, rng)
    return area, params


def perturb_environment(area: Area, perturbations: list[Perturbation], rng: np.random.Generator
                        ) -> tuple[Area, FieldChange | None, dict[str, float]]:
    """One ensemble member: the perturbed area, the change to the data it reads (None: no data
    kind) and the drawn parameters (name -> value, units in name).

    The area kinds are drawn first, in `Kind` order; a draw that makes the area invalid is
    redrawn (from the same generator, after the first draws: a member whose first draws are all
    valid is what the plain normal draws give). The data kinds (relief, water, front, month)
    draw after them, in the same order, into one ``envdata.fieldchange.FieldChange``.
    """
    params: dict[str, float] = {}
    area_kinds = [p for p in perturbations if p.kind not in FIELD_KINDS]
    for p, xi in zip(_ordered(area_kinds), draw(area_kinds, rng)):
        for _ in range(MAX_REDRAWS):
            try:
                area_p, values = _apply_one(area, p, xi)
                break
            except (AreaError, PerturbationError) as exc:  # outside the physical range: draw again
                last = exc
                xi = draw([p], rng)[0]
        else:
            raise PerturbationError(f"{p.source}: perturbation {p.describe()}: no valid draw in "
                                    f"{MAX_REDRAWS} tries on this member ({last})")
        area = area_p
        params.update(values)
    field_kinds = _ordered([p for p in perturbations if p.kind in FIELD_KINDS])
    if not field_kinds:
        return area, None, params
    change = FieldChange(origin_lat_deg=area.origin.lat_deg, origin_lon_deg=area.origin.lon_deg)
    for p in field_kinds:
        change, values = _draw_field(area, p, change, rng)
        params.update(values)
    return area, change, params


def member_area(area: Area, perturbations: list[Perturbation], seed: int,
                member: int) -> tuple[Area, dict[str, float]]:
    """Member ``member`` of the ensemble with seed ``seed`` (independent of who computes it)."""
    return perturb_area(area, perturbations, np.random.default_rng([seed, member]))


def member_environment(area: Area, perturbations: list[Perturbation], seed: int, member: int
                       ) -> tuple[Area, FieldChange | None, dict[str, float]]:
    """`perturb_environment` of member ``member`` (generator ``default_rng([seed, member])``)."""
    return perturb_environment(area, perturbations, np.random.default_rng([seed, member]))


def _truncated_normal(rng: np.random.Generator, n: int) -> np.ndarray:
    return draw([Perturbation(kind=Kind.EOF, sd=0.0, options=(("modes", float(n)), ("depth_m", 1.0)))], rng)[0]


def _draw_field(area: Area, p: Perturbation, change: FieldChange, rng: np.random.Generator
                ) -> tuple[FieldChange, dict[str, float]]:
    """One data kind drawn into ``change`` (see ``envdata.fieldchange``), and its parameters."""
    names = p.param_names()
    if p.kind is Kind.RELIEF:
        corr_m = 1000.0 * p.option("corr_km")  # the spec is in km
        field = SmoothField.draw(rng, (corr_m, corr_m))
        relief = ReliefChange(field=field, sd_m=p.sd, sd_frac=p.option("sd_frac"))
        new = dataclasses.replace(change, relief=relief)
        # the change of the water depth at the origin, for the parameter coordinate
        depth0 = 1000.0  # a reference depth, m: the fraction's part is reported at 1000 m
        f0 = float(field(0.0, 0.0))
        return new, {names[0]: depth0 * math.expm1(relief.sd_frac * f0) + relief.sd_m * f0}
    if p.kind is Kind.WATER:
        corr_m = 1000.0 * p.option("corr_km")  # the spec is in km
        scales = (corr_m, corr_m, p.option("scale_m"))
        t_field = SmoothField.draw(rng, scales)
        s_field = SmoothField.draw(rng, scales)
        sd_c, sd_psu = p.option("sd_c"), p.option("sd_psu")
        water = WaterChange(temperature_field=t_field, salinity_field=s_field,
                            sd_c=None if math.isnan(sd_c) else sd_c,
                            sd_psu=None if math.isnan(sd_psu) else sd_psu, factor=p.sd)
        return (dataclasses.replace(change, water=water),
                {names[0]: float(t_field(0.0, 0.0, 0.0)), names[1]: float(s_field(0.0, 0.0, 0.0))})
    if p.kind is Kind.FRONT:
        east, north = p.option("east_km"), p.option("north_km")
        if p.is_what_if:  # a fixed displacement: what if the front is there
            east, north = (0.0 if math.isnan(v) else v for v in (east, north))
        else:
            east, north = (p.sd * x for x in _truncated_normal(rng, 2))
        new = dataclasses.replace(change, front_east_m=1000.0 * east, front_north_m=1000.0 * north)
        return new, {names[0]: float(east), names[1]: float(north)}
    if p.kind is Kind.MONTH:
        offset = p.option("offset_months")
        if not p.is_what_if:
            offset = p.sd * float(_truncated_normal(rng, 1)[0])
        # within one month: a mix of the area's month and the neighbour on that side; beyond,
        # a whole number of months away: that month alone
        base = area.water.climatology.month
        if offset == 0.0:
            return change, {names[0]: 0.0}
        step = int(math.copysign(1, offset)) if abs(offset) <= 1.0 else int(offset)
        other = (base - 1 + step) % 12 + 1
        weight = min(abs(offset), 1.0)
        return dataclasses.replace(change, other_month=other, month_weight=weight), {names[0]: float(offset)}
    raise AssertionError(p.kind)  # pragma: no cover - every data kind is handled above


def _ordered(perturbations: list[Perturbation]) -> list[Perturbation]:
    order = list(Kind)
    return sorted(perturbations, key=lambda p: order.index(p.kind))


def _apply_one(area: Area, p: Perturbation, xi: np.ndarray) -> tuple[Area, dict[str, float]]:
    names = p.param_names()
    d = p.sd * float(xi[0])
    water, ssp = area.water, area.water.ssp
    if p.kind is Kind.DISPLACE:
        z, c = _dense(ssp)
        depth = water.depth_m
        if abs(d) * math.pi / depth >= 1.0:
            raise PerturbationError(f"{p.source}: perturbation {p.describe()}: a displacement of {d:g} m "
                                    f"in {depth:g} m of water makes the profile non-monotonic in depth "
                                    f"(need |d| pi / depth < 1 at {TRUNCATE_SD:g} sd)")
        c_new = np.interp(z - d * np.sin(math.pi * z / depth), z, c)
        return _with_profile(area, p, z, c_new), {names[0]: d}
    if p.kind is Kind.MIXED_LAYER:
        h = max(0.0, p.option("mean_m") + d)
        if h >= water.depth_m:
            raise PerturbationError(f"{p.source}: perturbation {p.describe()}: mixed layer depth {h:g} m "
                                    f"reaches the bottom at {water.depth_m:g} m")
        z, c = _dense(ssp)
        if h > 0:
            z_new = np.union1d(z, [h])
            c, z = np.interp(z_new, z, c), z_new
            c_h = float(np.interp(h, z, c))
            c = np.where(z <= h, c_h - ISOTHERMAL_GRADIENT_PER_S * (h - z), c)
        return _with_profile(area, p, z, c), {names[0]: h}
    if p.kind in (Kind.TEMPERATURE, Kind.SALINITY):
        z, c = _dense(ssp)
        shape = np.exp(-z / p.option("scale_m"))
        dt = d * shape if p.kind is Kind.TEMPERATURE else 0.0 * shape
        ds = d * shape if p.kind is Kind.SALINITY else 0.0 * shape
        c_new = c + teos10_speed_change_mps(z, c, dt, ds, latitude_deg=area.latitude_deg,
                                            longitude_deg=area.longitude_deg)
        return _with_profile(area, p, z, c_new), {names[0]: d}
    if p.kind is Kind.EOF:
        z, c = _dense(ssp)
        depth = p.option("depth_m")
        n = np.arange(1, p.n_draws + 1)
        amps = p.sd * np.asarray(xi, dtype=float) / n  # mode n has sd sd_mps / n
        modes = np.where(z[None, :] <= depth,
                         np.cos((n[:, None] - 0.5) * math.pi * np.minimum(z[None, :], depth) / depth), 0.0)
        return _with_profile(area, p, z, c + amps @ modes), dict(zip(names, amps.tolist()))
    if p.kind is Kind.WATER_DEPTH:
        new_depth = water.depth_m + d
        deepest = max([area.observer.depth_m] + [cls.depth_m for cls in area.classes])
        if new_depth <= deepest:
            raise PerturbationError(f"{p.source}: perturbation {p.describe()}: water depth {new_depth:g} m "
                                    f"is not below the deepest class or observer at {deepest:g} m")
        z, c = np.asarray(ssp.depth_m), np.asarray(ssp.speed_mps)
        if new_depth < water.depth_m:
            keep = z < new_depth
            z_new = np.append(z[keep], new_depth)
            c_new = np.append(c[keep], np.interp(new_depth, z, c))
        else:
            gradient = (c[-1] - c[-2]) / (z[-1] - z[-2])
            z_new = np.append(z, new_depth) if new_depth > z[-1] else z
            c_new = np.append(c, c[-1] + gradient * (new_depth - z[-1])) if new_depth > z[-1] else c
        profile = _profile(p, ssp, z_new, c_new)
        new_water = _wrap(p, Water, depth_m=new_depth, ssp=profile)
        grid = area.grid
        if grid.depth_step_m > new_depth:
            grid = dataclasses.replace(grid, depth_step_m=new_depth)
        return _wrap(p, dataclasses.replace, area, water=new_water, grid=grid), {names[0]: new_depth}
    if p.kind in (Kind.BOTTOM_SPEED, Kind.BOTTOM_DENSITY, Kind.BOTTOM_ATTENUATION):
        field_name = {Kind.BOTTOM_SPEED: "speed_mps", Kind.BOTTOM_DENSITY: "density_gcc",
                      Kind.BOTTOM_ATTENUATION: "attenuation_db_per_wavelength"}[p.kind]
        value = getattr(area.bottom, field_name) + d
        if value <= 0 and p.kind is Kind.BOTTOM_SPEED:
            raise PerturbationError(f"{p.source}: perturbation {p.describe()}: makes the bottom speed "
                                    f"non-positive ({value:g} m/s at {xi[0]:+g} sd)")
        if value < 0:
            raise PerturbationError(f"{p.source}: perturbation {p.describe()}: makes the bottom "
                                    f"{field_name} negative ({value:g} at {xi[0]:+g} sd)")
        bottom = _wrap(p, dataclasses.replace, area.bottom, **{field_name: value})
        return dataclasses.replace(area, bottom=bottom), {names[0]: value}
    if p.kind is Kind.SOURCE_DEPTH:
        factor = 1.0 + d
        if factor <= 0:
            raise PerturbationError(f"{p.source}: perturbation {p.describe()}: makes the class depths "
                                    f"non-positive (factor {factor:g} at {xi[0]:+g} sd)")
        classes = tuple(_wrap(p, dataclasses.replace, cls, depth_m=cls.depth_m * factor) for cls in area.classes)
        return _wrap(p, dataclasses.replace, area, classes=classes), {names[0]: factor}
    if p.kind is Kind.OBSERVER_DEPTH:
        depth = area.observer.depth_m + d
        return _wrap(p, dataclasses.replace, area, observer=Observer(depth_m=depth)), {names[0]: depth}
    raise AssertionError(p.kind)  # pragma: no cover - every Kind is handled above


def _wrap(p: Perturbation, fn, *args, **kwargs):
    try:
        return fn(*args, **kwargs)
    except AreaError as exc:
        raise PerturbationError(f"{p.source}: perturbation {p.describe()}: {exc}") from None


def _dense(ssp: SoundSpeedProfile) -> tuple[np.ndarray, np.ndarray]:
    """The profile on its own depths plus a regular grid fine enough for smooth perturbations."""
    bottom = ssp.bottom_m
    step = min(25.0, bottom / 100.0)
    z = np.union1d(np.asarray(ssp.depth_m), np.arange(0.0, bottom, step))
    return z, np.interp(z, ssp.depth_m, ssp.speed_mps)


def _profile(p: Perturbation, ssp: SoundSpeedProfile, z, c) -> SoundSpeedProfile:
    c = np.asarray(c, dtype=float)
    if np.any(c <= 0):
        i = int(np.argmax(c <= 0))
        raise PerturbationError(f"{p.source}: perturbation {p.describe()}: makes a speed non-positive "
                                f"({c[i]:.1f} m/s at {z[i]:g} m)")
    i = speed_outside(c)
    if i is not None:
        raise PerturbationError(f"{p.source}: perturbation {p.describe()}: makes the speed {c[i]:.1f} m/s "
                                f"at {z[i]:g} m, outside [{MIN_SPEED_MPS:g}, {MAX_SPEED_MPS:g}] m/s")
    return _wrap(p, SoundSpeedProfile, depth_m=tuple(float(v) for v in z),
                 speed_mps=tuple(float(v) for v in np.round(c, 3)), kind=ssp.kind,
                 interpolation=ssp.interpolation)


def _with_profile(area: Area, p: Perturbation, z, c) -> Area:
    water = _wrap(p, Water, depth_m=area.water.depth_m, ssp=_profile(p, area.water.ssp, z, c))
    return dataclasses.replace(area, water=water)


def teos10_speed_change_mps(depth_m, speed_mps, dt_c, ds_psu, *, latitude_deg: float,
                            longitude_deg: float) -> np.ndarray:
    """Change of sound speed for in-situ temperature and salinity changes, by TEOS-10 (gsw).

    The profile's temperature is inferred from its speed at practical salinity 35 (Newton on
    gsw.sound_speed), then the speed is recomputed with T + dT, S + dS.
    """
    import gsw

    z = np.asarray(depth_m, dtype=float)
    c = np.asarray(speed_mps, dtype=float)
    p_dbar = gsw.p_from_z(-z, latitude_deg)
    sp = np.full_like(z, REFERENCE_SALINITY_PSU)

    def speed(t, s):
        sa = gsw.SA_from_SP(s, p_dbar, longitude_deg, latitude_deg)
        return gsw.sound_speed(sa, gsw.CT_from_t(sa, t, p_dbar), p_dbar)

    t = np.full_like(z, 10.0)
    for _ in range(8):
        f0 = speed(t, sp) - c
        slope = (speed(t + 0.01, sp) - speed(t - 0.01, sp)) / 0.02
        t = np.clip(t - f0 / slope, -2.0, 40.0)
    dt = np.broadcast_to(np.asarray(dt_c, dtype=float), z.shape)
    ds = np.broadcast_to(np.asarray(ds_psu, dtype=float), z.shape)
    t_new, s_new = t + dt, sp + ds
    if np.any((t_new < -2.5) | (t_new > 40.0)):
        i = int(np.argmax((t_new < -2.5) | (t_new > 40.0)))
        raise AreaError(f"temperature {t_new[i]:.2f} degC at {z[i]:g} m is outside [-2.5, 40] degC")
    if np.any((s_new < 0.0) | (s_new > 42.0)):
        i = int(np.argmax((s_new < 0.0) | (s_new > 42.0)))
        raise AreaError(f"salinity {s_new[i]:.2f} at {z[i]:g} m is outside [0, 42]")
    return speed(t + dt, sp + ds) - speed(t, sp)
