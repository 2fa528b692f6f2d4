"""The arrivals run that puts the surface at a target that is the receiver (tables from the
observer), and its rows in a band's TL (``acoustics.builder.surfaceimage``).

One arrivals run per table from the observer (a radial, or a flat grid's ``tl_obs_db``), its
water mirrored above the surface: the fan's angles with more beams (``Propagation.image_beams``),
receivers at the depths within the surface's reach (and their mirror images) of the lowest
band (the grid's depths there, the classes' and ``SURFACE_ROW_M``), at the lowest band's centre
frequency (geometric beams do not depend on frequency but through volume attenuation, which the
reduction rescales). Its result replaces those rows of every band's TL.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from acoustics.absorption import absorption_db_per_km
from acoustics.bellhop.envfile import RunSpec
from acoustics.builder.bandruns import run_timeout_s, surface_acts
from acoustics.builder.plan import run_spec
from acoustics.builder.runs import Run
from acoustics.builder.surfaceimage import ImageBand, SurfaceImage
from acoustics.kcurve import band_weights
from acoustics.surface import band_quadrature, surface_reach_m
from envdata.area import Absorption, Area


def image_rows(area: Area, receivers_m, speed_of: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
    """Indices of ``receivers_m`` within the surface's reach of any band (none outside the
    semicoherent mode)."""
    z = np.asarray(receivers_m, dtype=float)
    c = speed_of(z)
    return np.flatnonzero([any(surface_acts(area, band, float(zi), float(ci)) for band in area.bands)
                           for zi, ci in zip(z, c)])


def surface_image(area: Area, run_hz: float, depths_m: np.ndarray, speeds_mps: np.ndarray) -> SurfaceImage:
    """The reduction of the arrivals run: per receiver depth and band, the band's quadrature for
    that depth (``band_quadrature``: as many frequencies as the Lloyd factor's turns across the band
    at that depth need, `IMAGE_POINTS_PER_TURN` a turn, half what the band runs' source end takes;
    below the band's reach, the reach's), each frequency's volume attenuation relative to
    ``run_hz``, and each class's weights."""
    speeds = tuple(round(float(c), 3) for c in speeds_mps)
    rows = tuple(tuple(_image_band(area, band, float(z), c, run_hz) for band in area.bands)
                 for z, c in zip(depths_m, speeds))
    return SurfaceImage(receiver_depth_m=tuple(float(z) for z in depths_m), speed_mps=speeds, bands=rows,
                        tl_max_db=float(area.propagation.tl_max_db))


#: The reduction's quadrature: frequencies per turn of the Lloyd factor across the band, and the
#: fewest a row takes. Half the source end's (8, 33): on shelf-break's arrivals runs the band TL
#: of the near-surface rows moves by 0.0006 dB median, 0.03 dB at the 99th percentile and 0.32 dB
#: at most, and the reduction takes half the time (notes of the stop that chose it).
IMAGE_POINTS_PER_TURN, IMAGE_MIN_POINTS = 4, 17


def _image_band(area: Area, band, depth_m: float, speed_mps: float, run_hz: float) -> ImageBand:
    # below the band's reach the factor averages out: the reach's quadrature serves
    freqs, _ = band_quadrature(area.classes[0], band, min(depth_m, surface_reach_m(band, speed_mps)), speed_mps,
                               points_per_turn=IMAGE_POINTS_PER_TURN, min_points=IMAGE_MIN_POINTS)
    if area.propagation.absorption is Absorption.NONE:
        ratio = np.ones(freqs.size)
    else:
        ratio = absorption_db_per_km(freqs, area.propagation.absorption) \
            / absorption_db_per_km(run_hz, area.propagation.absorption)
    weights = np.stack([band_weights(cls, freqs) for cls in area.classes])
    return ImageBand(freqs_hz=_frozen(freqs), attenuation_ratio=_frozen(ratio), weights=_frozen(weights))


def _frozen(values) -> np.ndarray:
    a = np.ascontiguousarray(values, dtype=np.float64)
    a.setflags(write=False)
    return a


def plan_image_run(area: Area, receivers_m, speed_of: Callable[[np.ndarray], np.ndarray],
                   make_files: Callable[[RunSpec], dict[str, str]], *, title: str
                   ) -> tuple[np.ndarray, Run] | None:
    """(receiver rows, run) of the arrivals run a table from the observer needs (None where the
    surface acts on none of its receivers), its water mirrored above the surface; ``make_files``
    turns the run's spec into its files (``env`` and any others)."""
    prop = area.propagation
    rng = area.grid.range_m()
    receivers = np.asarray(receivers_m, dtype=float)
    rows = image_rows(area, receivers, speed_of)
    if rows.size == 0:
        return None
    depths = receivers[rows]
    run_hz = float(area.bands[0].center_hz)
    n_beams = prop.image_beams
    spec = run_spec(area, title=f"{title} surface image", freq_hz=run_hz,
                    source_depths_m=(area.observer.depth_m,), receiver_depths_m=depths, ranges_m=rng,
                    fan=(n_beams, prop.angle_min_deg, prop.angle_max_deg), arrivals=True, mirror_surface=True)
    files = make_files(spec)
    image = surface_image(area, run_hz, depths, speed_of(depths))
    run = Run(env=files.pop("env"), files=tuple(files.items()), freq_hz=run_hz,
              source_depth_m=area.observer.depth_m, n_beams=n_beams, image=image,
              timeout_s=run_timeout_s(area, n_beams, depths.size * rng.size))
    return rows, run


def with_image_rows(band_tl_db: np.ndarray, rows: np.ndarray, image_tl_db: np.ndarray,
                    ic: int, ib: int) -> np.ndarray:
    """A band's TL (receiver, range) with the arrivals run's rows of class ``ic``, band ``ib``."""
    out = np.array(band_tl_db, dtype=float, copy=True)
    out[rows] = image_tl_db[ic, ib]
    return out
