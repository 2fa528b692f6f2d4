"""The surface at a target that is the receiver: the near-surface rows of a table from the observer.

Tables from the observer (bearing-dependent grids and atlases, ``tl_obs_db``, K by reciprocity)
have the source at the observer and the target at the receiver, so the surface's interference
belongs at the receiver's end, where BELLHOP's source pattern cannot put it. And incoherent hat
beams under-count receivers near the surface: a beam wider than the receiver's depth reaches it
on one leg of its reflection only, so with the default fan K of a 6 m target from the observer
came out 2.1 dB lossier than from the target (ocean-deep, 60 km; 1.5 dB at 12 m, 0.8 dB at
20 m, nothing below 40 m).

One arrivals run (run type 'a') from the observer, with more beams than the fan
(``Propagation.image_beams``) and receivers only at the depths within the surface's reach, gives
every arrival's intensity I (spreading and bottom loss; volume attenuation at the run's frequency, rescaled to each
frequency of a band through its path's attenuation), its angle theta at the receiver and its
surface reflections. Each arrival and its surface image form a pair that carries the Lloyd
factor G(theta) of ``acoustics.surface``; where the pair's twin is in the list (opposite
direction, the same angle, one surface reflection more or less) the stronger of the two gives
the pair's intensity, and where it is missing (the hat-beam truncation at the surface) it is
restored:

    I_row = sum over pairs of max(I_a, I_b) (G_a + G_b)      (a twin missing: 2 I_a G_a)

The pairs are geometry: found once per receiver, strongest first by the intensities at the run
frequency, and summed with each band's and class's intensities and factors. (Finding them again
for every band and class, as before, took a third of the reduction; it moved 30 of 151,200
near-surface cells of shelf-break's first four radials, where two arrivals of nearly equal
intensity swapped rank between bands, by up to 0.7 dB, and left the rest identical.)

The band average runs over the band's quadrature with the class's spectrum, as many frequencies
at each receiver depth as the Lloyd factor's turns across the band there need (``band_quadrature``
with ``acoustics.builder.imageruns.IMAGE_POINTS_PER_TURN``). Measured on
ocean-deep (a 6 m target, the 100 m observer, 2-60 km) against the run from the target with
the Lloyd pattern: K differs by 0.92 / 0.65 / 0.18 / 0.03 dB median with 1500 / 3000 / 4000 /
6000 beams over +-80 deg, where the incoherent field's row differs by 1.9-2.1 dB and the field
times the band-averaged factor by 2.0 / 1.4 / 1.1 / 0.6 dB (docs/models.md "The sea surface").

The worker that runs BELLHOP reduces the arrivals at once (``image_tl_db``), so what travels back
and is cached is one small array per run: TL (class, band, receiver depth, range).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import numpy as np

from acoustics.bellhop.arrfile import Arrivals

#: Two arrivals at one receiver are a pair when their angles' magnitudes differ by less than this,
#: deg, or than 1.5 times the angle 2 z / r that separates a ray from its image at depth z and range r.
PAIR_ANGLE_DEG = 0.5


@dataclass(frozen=True, slots=True, eq=False)
class ImageBand:
    """One band: its quadrature frequencies (``acoustics.surface.band_quadrature``), each one's
    volume attenuation relative to the run frequency's (ratio; 1 without absorption), and the
    weights of each class's spectrum, ``weights[class]``: read-only float64 arrays, (n,), (n,)
    and (class, n)."""

    freqs_hz: np.ndarray
    attenuation_ratio: np.ndarray
    weights: np.ndarray


@dataclass(frozen=True, slots=True, eq=False)
class SurfaceImage:
    """What an arrivals run is reduced to: its receivers' depths (m) and sound speeds (m/s), the
    bands' quadratures at each receiver depth (``bands[depth][band]``), and the shadow cap (dB)."""

    receiver_depth_m: tuple[float, ...]
    speed_mps: tuple[float, ...]
    bands: tuple[tuple[ImageBand, ...], ...]
    tl_max_db: float
    #: the run's water is mirrored above the surface (``RunSpec.mirror_surface``): its receivers
    #: are at each depth and its mirror, and the reduction sums both (``mirrored_tl_db``)
    mirrored: bool = False

    @property
    def digest(self) -> str:
        """A hash of everything the reduction uses (part of the run's key)."""
        h = hashlib.sha256(repr((self.receiver_depth_m, self.speed_mps, self.tl_max_db, self.mirrored)).encode())
        for row in self.bands:
            for b in row:
                for a in (b.freqs_hz, b.attenuation_ratio, b.weights):
                    h.update(repr(a.shape).encode())
                    h.update(np.ascontiguousarray(a, dtype=np.float64).tobytes())
        return h.hexdigest()


def image_tl_db(arrivals: Arrivals, image: SurfaceImage) -> np.ndarray:
    """Band TL at the run's receivers with the surface at their end, ``(class, band, receiver
    depth, range)``, float32, dB (``tl_max_db`` where nothing arrives)."""
    if image.mirrored:
        return mirrored_tl_db(arrivals, image)
    nz, nr = arrivals.count.shape
    if nz != len(image.receiver_depth_m):
        raise ValueError(f"arrivals for {nz} receiver depths, image for {len(image.receiver_depth_m)}")
    offsets = np.concatenate([[0], np.cumsum(arrivals.count.ravel())]).astype(np.int64)
    r_r = np.maximum(np.asarray(arrivals.range_m, dtype=float), 1.0)
    floor = 10.0 ** (-image.tl_max_db / 10.0)
    n_class = len(image.bands[0][0].weights) if image.bands and image.bands[0] else 0
    n_band = len(image.bands[0]) if image.bands else 0
    out = np.empty((n_class, n_band, nz, nr), dtype=np.float32)
    # one receiver depth at a time (the arrivals are stored depth-major: each depth's are one run
    # of them): the per-arrival work arrays then hold one depth's arrivals, not the run's
    for iz in range(nz):
        first, last = offsets[iz * nr], offsets[(iz + 1) * nr]
        rows = slice(first, last)
        z, c = float(image.receiver_depth_m[iz]), float(image.speed_mps[iz])
        depth, speed = np.full(last - first, z), np.full(last - first, c)
        amplitude2 = arrivals.amplitude[rows] ** 2
        # volume attenuation at the run frequency (|p| = A exp(omega Im tau)), as intensity
        attenuation = np.exp(2.0 * 2.0 * np.pi * arrivals.freq_hz * arrivals.delay_imag_s[rows])
        angle, bounces = arrivals.receiver_angle_deg[rows], arrivals.surface_bounces[rows]
        row_offsets = offsets[iz * nr:(iz + 1) * nr + 1] - first
        tolerance = np.maximum(PAIR_ANGLE_DEG, 1.5 * np.degrees(2.0 * z / r_r))
        # the pairs are geometry: found once, by the intensities at the run frequency
        twin = _image_twins(amplitude2 * attenuation, angle, bounces, row_offsets, tolerance)
        for ib, band in enumerate(image.bands[iz]):
            # each arrival's band averages of I(f) and of I(f) G(theta, f): attenuation and the
            # Lloyd factor vary together over the band
            plain, lloyd = _band_sums(attenuation, depth, speed, angle, band)
            for ic in range(n_class):
                # in place: the factor in lloyd's row, the intensity in plain's
                factor = np.divide(lloyd[ic], np.maximum(plain[ic], 1e-300), out=lloyd[ic])
                intensity = np.multiply(amplitude2, plain[ic], out=plain[ic])
                total = _twin_sums(intensity, factor, twin, row_offsets)
                out[ic, ib, iz] = -10.0 * np.log10(np.maximum(total, floor))
    return out


def mirrored_tl_db(arrivals: Arrivals, image: SurfaceImage) -> np.ndarray:
    """``image_tl_db`` of a run whose water is mirrored above the surface: at each row z the
    arrivals at z (the paths that end there without a last surface reflection) and at -z (the
    mirror images of those that end with one) carry the intensity of a pair each, and each its
    Lloyd factor, band-averaged with the class's spectrum and the volume attenuation across the
    band:

        I_row = sum over the arrivals at z and at -z of I_a G(theta_a)

    No pairing and no restoring: a hat beam is never cut at a surface here, so the two members
    of a pair arrive whole, each at its own receiver."""
    depths = np.asarray(arrivals.receiver_depth_m, dtype=float)
    nr = arrivals.count.shape[1]
    offsets = np.concatenate([[0], np.cumsum(arrivals.count.ravel())]).astype(np.int64)
    floor = 10.0 ** (-image.tl_max_db / 10.0)
    n_class = len(image.bands[0][0].weights) if image.bands and image.bands[0] else 0
    n_band = len(image.bands[0]) if image.bands else 0
    out = np.empty((n_class, n_band, len(image.receiver_depth_m), nr), dtype=np.float32)
    for iz, (z, c) in enumerate(zip(image.receiver_depth_m, image.speed_mps)):
        mirror = [int(np.flatnonzero(np.isclose(depths, d, rtol=0.0, atol=1e-6))[0]) for d in {z, -z}]
        spans = [slice(offsets[q * nr], offsets[(q + 1) * nr]) for q in mirror]
        amplitude2 = np.concatenate([arrivals.amplitude[s] for s in spans]) ** 2
        attenuation = np.exp(2.0 * 2.0 * np.pi * arrivals.freq_hz
                             * np.concatenate([arrivals.delay_imag_s[s] for s in spans]))
        angle = np.concatenate([arrivals.receiver_angle_deg[s] for s in spans])
        at_range = np.concatenate([np.repeat(np.arange(nr), arrivals.count[q]) for q in mirror])
        depth, speed = np.full(angle.size, float(z)), np.full(angle.size, float(c))
        for ib, band in enumerate(image.bands[iz]):
            _, lloyd = _band_sums(attenuation, depth, speed, angle, band)
            for ic in range(n_class):
                total = np.bincount(at_range, weights=amplitude2 * lloyd[ic], minlength=nr)
                out[ic, ib, iz] = -10.0 * np.log10(np.maximum(total, floor))
    return out


def _band_sums(attenuation, depth, speed, angle_deg, band: ImageBand) -> tuple[np.ndarray, np.ndarray]:
    """Each arrival's band averages per class (``acoustics.builder._pairs``, numba)."""
    from acoustics.builder._pairs import band_sums  # compiled on first use, in the worker

    def arr(x):
        return np.ascontiguousarray(x, dtype=np.float64)

    return band_sums(arr(attenuation), arr(depth), arr(speed), arr(angle_deg), band.freqs_hz,
                     band.attenuation_ratio, band.weights)


def _image_twins(intensity, angle_deg, bounces, offsets, tolerance_deg) -> np.ndarray:
    """Each arrival's surface twin at its receiver (``acoustics.builder._pairs``, numba)."""
    from acoustics.builder._pairs import image_twins  # compiled on first use, in the worker

    return image_twins(np.ascontiguousarray(intensity, dtype=np.float64),
                       np.ascontiguousarray(angle_deg, dtype=np.float64),
                       np.ascontiguousarray(bounces, dtype=np.float64), offsets,
                       np.ascontiguousarray(tolerance_deg, dtype=np.float64))


def _twin_sums(intensity, factor, twin, offsets) -> np.ndarray:
    """Per receiver, the sum over image pairs (``acoustics.builder._pairs``, numba)."""
    from acoustics.builder._pairs import twin_sums  # compiled on first use, in the worker

    return twin_sums(np.ascontiguousarray(intensity, dtype=np.float64),
                     np.ascontiguousarray(factor, dtype=np.float64), twin, offsets)
