"""One coherent RAM run (easypyram) on a receiver grid: TL(depth, range) in dB.

easypyram's orientation, which this module alone handles: its sound speed ``cw`` is
(depth points, range points), ours ``RamEnvironment.speed_mps`` is (range, depth); its output
fields are (depth, range), as ours. Its complex output excludes the cylindrical spreading
1/sqrt(r) and the carrier exp(i k0 r): it is the slowly varying envelope, which is what is
interpolated here.

How the requested receivers are served from RAM's own grid:

- ranges: when every requested range is a whole multiple of the smallest one (a grid axis
  ``step, 2 step, ...``), the range step is shortened to ``step / n`` (n the least integer with
  ``step / n <= settings.range_step_m``) and RAM writes every n-th step, so its output falls
  exactly on the requested ranges; otherwise RAM writes every step and the envelope is
  interpolated linearly between the two steps around each range (the envelope's phase moves by
  about k0 (1 - cos theta) dr per step, well under 0.1 rad for dr <= lambda / 2 and angles to
  20 deg). A range shorter than RAM's first step takes the first step's value.
- depths: RAM writes every point of its depth grid down to the deepest requested depth, and the
  complex envelope is interpolated linearly between the two grid points around each depth, the
  surface (pressure 0) included (dz <= lambda / 10 keeps the phase change per point < 0.7 rad at
  vertical incidence and far less at the shallow angles that carry the field).

TL = -20 lg |p| + 10 lg r with p the envelope, dB re 1 m, capped at ``tl_max_db`` where the
pressure vanishes (as BELLHOP's grids are); then the environment's volume absorption is added as
alpha(f) r (RAM has none; its field travels within a few tens of degrees of horizontal, where
the path is at most a few per cent longer than r). Receivers below the bottom, or beyond the
environment's end, are NaN.
"""

from __future__ import annotations

import math

import numpy as np

from acoustics.absorption import absorption_db_per_km
from acoustics.ram.environment import RamEnvironment
from acoustics.ram.errors import RamInputError, RamRunError
from acoustics.ram.settings import RamSettings
from envdata.limits import check_memory

#: Range-dependent sound speed reaches RAM as piecewise-constant columns this far apart, m, each
#: the section's linear interpolation at the middle of its stretch.
SSP_COLUMN_STEP_M = 500.0
#: Relative tolerance for "a requested range is a whole multiple of the smallest".
GRID_TOLERANCE = 1e-6
#: Bytes per point of RAM's output grid: easypyram's complex and real fields, and ours.
BYTES_PER_OUTPUT_POINT = 48


def ram_tl_db(env: RamEnvironment, freq_hz: float, depth_m, range_m, settings: RamSettings, *,
              tl_max_db: float = 200.0) -> np.ndarray:
    """Coherent transmission loss of one RAM run on a receiver grid.

    Parameters
    ----------
    env : RamEnvironment
        The 2-D environment, source at range 0.
    freq_hz : float
        Frequency, Hz (> 0).
    depth_m : array_like, shape (D,)
        Receiver depths, m (>= 0).
    range_m : array_like, shape (R,)
        Receiver ranges from the source, m (> 0).
    settings : RamSettings
        Steps, Pade terms, grid depth (``RamSettings.for_frequency`` gives the defaults). Its
        ``grid_depth_m - absorbing_layer_m`` must reach the environment's deepest bottom.
    tl_max_db : float
        TL where the pressure vanishes (the surface, deep shadows), dB; as BELLHOP's grids.

    Returns
    -------
    tl_db : ndarray, shape (D, R)
        Coherent TL, dB re 1 m, volume absorption included; NaN below the bottom (deeper than
        the environment's bottom at that range) and beyond ``env.end_range_m``.

    Raises
    ------
    RamInputError
        A frequency, depth or range out of range, or settings whose grid does not reach below
        the deepest bottom.
    RamRunError
        easypyram failed (its message quoted).
    """
    depth = _axis(depth_m, "depth_m", allow_zero=True)
    rng = _axis(range_m, "range_m", allow_zero=False)
    if not (math.isfinite(freq_hz) and freq_hz > 0.0):
        raise RamInputError(f"RAM run: frequency must be > 0 Hz, got {freq_hz}")
    if not (math.isfinite(tl_max_db) and tl_max_db > 0.0):
        raise RamInputError(f"RAM run: tl_max_db must be > 0 dB, got {tl_max_db}")
    top_of_layer_m = settings.grid_depth_m - settings.absorbing_layer_m
    if top_of_layer_m < env.max_bottom_depth_m - 1e-6:
        raise RamInputError(f"RAM settings grid_depth_m: {settings.grid_depth_m} m leaves the absorbing layer "
                            f"({settings.absorbing_layer_m} m) starting at {top_of_layer_m} m, above the "
                            f"deepest bottom, {env.max_bottom_depth_m} m")
    top_of_layer_m = max(top_of_layer_m, env.max_bottom_depth_m)  # rounding in grid - layer
    if settings.depth_step_m >= env.bathymetry_depth_m[0] / 2:
        raise RamInputError(f"RAM settings depth_step_m: {settings.depth_step_m} m is too coarse for "
                            f"{float(env.bathymetry_depth_m[0])} m of water at the source")

    end_m = env.end_range_m if env.end_range_m is not None else math.inf
    wet = rng <= end_m
    out = np.full((depth.size, rng.size), np.nan)
    if not np.any(wet):
        return out
    reach_m = float(rng[wet].max())
    dr_m, ndr, n_out, n_z = _output_grid(env, depth, rng[wet], settings)
    dz_m = settings.depth_step_m
    check_memory(float(BYTES_PER_OUTPUT_POINT) * n_z * n_out, f"a RAM run at {freq_hz:g} Hz to {reach_m:g} m")

    c0 = settings.reference_speed_mps or _mean_water_speed_mps(env)
    wavelength_m = c0 / freq_hz
    rmax_m = (n_out + 0.5) * dr_m * ndr  # easypyram writes floor(rmax / (dr ndr)) ranges: n_out
    ssp_z, ssp_r, cw = _ram_section(env, top_of_layer_m, rmax_m)
    bottom = env.bottom
    kwargs = dict(np=settings.pade_terms, ns=settings.stability_terms, c0=c0, dr=dr_m, dz=dz_m, ndr=ndr,
                  ndz=1, zmplt=(n_z + 0.5) * dz_m, rmax=rmax_m, lyrw=settings.absorbing_layer_m / wavelength_m)
    if settings.stability_range_m is not None:
        kwargs["rs"] = settings.stability_range_m
    rbzb = np.column_stack([env.bathymetry_range_m, env.bathymetry_depth_m])
    from easypyram import PyRAM  # here, not at import: numba's start-up (~1.7 s) only for a RAM run

    try:
        model = PyRAM(freq_hz, env.source_depth_m, env.source_depth_m, ssp_z, ssp_r, cw,
                      np.array([0.0]), np.array([0.0]), np.array([[bottom.speed_mps]]),
                      np.array([[bottom.density_gcc]]), np.array([[bottom.attenuation_db_per_wavelength]]),
                      rbzb, **kwargs)
        result = model.run()
    except (ValueError, ZeroDivisionError, FloatingPointError) as exc:
        raise RamRunError(f"RAM (easypyram) failed at {freq_hz:g} Hz with dr {dr_m:g} m, dz {dz_m:g} m, "
                          f"{settings.pade_terms} Pade terms: {exc}") from None
    out_r = np.asarray(result.ranges, dtype=float)      # (nvr,)
    out_z = np.asarray(result.depths, dtype=float)      # (nvz,): dz, 2 dz, ...
    envelope = np.asarray(result.pressure_grid)          # (nvz, nvr): easypyram's (depth, range)
    if envelope.shape != (out_z.size, out_r.size):
        raise RamRunError(f"RAM (easypyram) returned a field of shape {envelope.shape} for {out_z.size} "
                          f"depths x {out_r.size} ranges")
    # the pressure-release surface: zero pressure at depth 0, for depths above the first point
    out_z = np.concatenate([[0.0], out_z])
    envelope = np.concatenate([np.zeros((1, out_r.size), dtype=envelope.dtype), envelope], axis=0)

    at_depth = _interp_rows(envelope, out_z, depth)               # (D, nvr)
    field = _interp_rows(at_depth.T, out_r, rng[wet]).T           # (D, R wet)
    magnitude = np.abs(field) / np.sqrt(rng[wet])[None, :]        # 1/sqrt(r): cylindrical spreading
    floor = 10.0 ** (-tl_max_db / 20.0)
    tl = -20.0 * np.log10(np.maximum(magnitude, floor))
    alpha_db_per_km = float(absorption_db_per_km(freq_hz, env.absorption))
    tl = np.minimum(tl + alpha_db_per_km * rng[wet][None, :] / 1000.0, tl_max_db)  # alpha in dB/km
    below = depth[:, None] > env.bottom_depth_m(rng[wet])[None, :] + 1e-6
    out[:, wet] = np.where(below, np.nan, tl)
    return out


def ram_run_bytes(env: RamEnvironment, depth_m, range_m, settings: RamSettings) -> float:
    """Memory one RAM run keeps at its peak, bytes: its whole output field (easypyram holds it all,
    complex and real, before ``ram_tl_db`` interpolates it), `BYTES_PER_OUTPUT_POINT` per point.

    Parameters as `ram_tl_db` (the frequency acts through ``settings``' steps).
    """
    depth = _axis(depth_m, "depth_m", allow_zero=True)
    rng = _axis(range_m, "range_m", allow_zero=False)
    end_m = env.end_range_m if env.end_range_m is not None else math.inf
    wet = rng[rng <= end_m]
    if wet.size == 0:
        return 0.0
    _, _, n_out, n_z = _output_grid(env, depth, wet, settings)
    return float(BYTES_PER_OUTPUT_POINT) * n_z * n_out


def _output_grid(env: RamEnvironment, depth: np.ndarray, wet_range_m: np.ndarray,
                 settings: RamSettings) -> tuple[float, int, int, int]:
    """RAM's range step, output decimation, number of output ranges and of output depths."""
    reach_m = float(wet_range_m.max())
    dr_m, ndr = _range_step(wet_range_m, settings.range_step_m)
    n_out = max(1, int(math.ceil(reach_m / (dr_m * ndr) - GRID_TOLERANCE)))
    dz_m = settings.depth_step_m
    deepest_m = min(float(depth.max()), env.max_bottom_depth_m)
    # RAM's output depths dz, 2 dz, ... past the deepest wanted one, inside the grid
    n_z = min(int(math.floor(deepest_m / dz_m)) + 2, int(math.floor(settings.grid_depth_m / dz_m)) - 2)
    return dr_m, ndr, n_out, n_z


def _axis(values, name: str, *, allow_zero: bool) -> np.ndarray:
    arr = np.asarray(values, dtype=float)
    if arr.ndim != 1 or arr.size == 0:
        raise RamInputError(f"RAM run {name}: need a 1-D array of at least one value, got shape {arr.shape}")
    low_ok = arr >= 0.0 if allow_zero else arr > 0.0
    if not np.all(np.isfinite(arr) & low_ok):
        bad = arr[~(np.isfinite(arr) & low_ok)][0]
        raise RamInputError(f"RAM run {name}: values must be finite and {'>=' if allow_zero else '>'} 0 m, "
                            f"got {bad}")
    return arr


def _range_step(range_m: np.ndarray, step_m: float) -> tuple[float, int]:
    """RAM's step and output decimation: (step, n) with the outputs exactly on the ranges when
    they are whole multiples of the smallest one, else (settings' step, 1)."""
    base = float(range_m.min())
    ratio = range_m / base
    if np.all(np.abs(ratio - np.round(ratio)) <= GRID_TOLERANCE * np.maximum(ratio, 1.0)):
        n = max(1, int(math.ceil(base / step_m - GRID_TOLERANCE)))
        return base / n, n
    return step_m, 1


def _mean_water_speed_mps(env: RamEnvironment) -> float:
    """Depth average of the sound speed in the water at range 0, m/s."""
    z = env.ssp_depth_m
    c = env.speed_mps[0]
    bottom = float(env.bathymetry_depth_m[0])
    zz = np.linspace(0.0, bottom, 201)
    return float(np.mean(np.interp(zz, z, c)))


def _ram_section(env: RamEnvironment, top_of_layer_m: float, rmax_m: float):
    """easypyram's (z_ss, rp_ss, cw) with cw (depth, range): the section cut or continued to the
    top of the absorbing layer, and, when it varies with range, columns every
    `SSP_COLUMN_STEP_M` (easypyram holds each column until the next one)."""
    z = env.ssp_depth_m
    keep = z < top_of_layer_m - 1e-9
    ssp_z = np.concatenate([z[keep], [top_of_layer_m]])
    if env.ssp_range_m.size == 1:
        ssp_r = np.array([0.0])
        columns = env.speed_mps[:1]
    else:
        n = max(1, int(math.ceil(rmax_m / SSP_COLUMN_STEP_M)))
        ssp_r = SSP_COLUMN_STEP_M * np.arange(n)
        columns = np.stack([env.speed_at_mps(r + 0.5 * SSP_COLUMN_STEP_M) for r in ssp_r])
    # below the section's last depth the deepest speed is held; RAM uses the water's speed only
    # above the bottom, so rows under it matter only as a table easypyram can read
    cw = np.stack([np.interp(ssp_z, z, col) for col in columns], axis=1)  # (depth, range)
    return ssp_z, ssp_r, cw


def _interp_rows(values: np.ndarray, x: np.ndarray, at: np.ndarray) -> np.ndarray:
    """Rows of ``values`` (along ``x``, first axis) interpolated linearly at ``at``, complex;
    ``at`` outside ``x`` takes the nearest end row."""
    i = np.clip(np.searchsorted(x, at, side="right") - 1, 0, x.size - 1)
    j = np.minimum(i + 1, x.size - 1)
    span = np.where(j > i, x[j] - x[i], 1.0)
    w = np.clip((at - x[i]) / span, 0.0, 1.0)
    return values[i] * (1.0 - w)[:, None] + values[j] * w[:, None]
