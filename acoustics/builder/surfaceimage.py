"""The surface at a target that is the receiver: the near-surface rows of a table from the observer.

Tables from the observer (bearing-dependent grids and atlases, ``tl_obs_db``, K by reciprocity)
have the source at the observer and the target at the receiver, so the surface's interference
belongs at the receiver's end, where BELLHOP's source pattern cannot put it.

One arrivals run (run type 'a') from the observer, with more beams than the fan
(``Propagation.image_beams``) and receivers only at the depths within the surface's reach, gives
every arrival's intensity I (spreading and bottom loss; volume attenuation at the run's
frequency, rescaled to each frequency of a band through its path's attenuation) and its angle
theta at the receiver. The run's water is mirrored above the surface (``RunSpec.mirror_surface``):
no surface, the profile mirrored at 0 and the bottom's half-space at the bottom's mirror image.
A path that reflects at the sea surface runs on through the mirror instead (the method of
images), so at a row z the paths that end without a last surface reflection arrive at z and
those that end with one at -z, each whole: a hat beam is never cut short at a surface there.
Each of them carries the Lloyd factor G(theta) = 2 sin^2(k z sin theta) of ``acoustics.surface``
(the interference of the pair it belongs to, whose other member is the mirror arrival):

    I_row = sum over the arrivals at z and at -z of I_a G(theta_a)

The band average runs over the band's quadrature with the class's spectrum, as many frequencies
at each receiver depth as the Lloyd factor's turns across the band there need (``band_quadrature``
with ``acoustics.builder.imageruns.IMAGE_POINTS_PER_TURN``).

The run with the surface it replaced paired each arrival with its surface twin at the same
receiver and restored a twin the hat beams' truncation at the surface had cut (a beam wider than
the receiver's depth reaches it on one leg of its reflection only). That pairing was biased where
beams are wide: on shelf-break the ships' K came out 1-1.8 dB louder in the mean than BELLHOP run
from the ship along each true path, where the mirrored run is within 0.31 dB in the mean with half
its beams (``docs/results/image-mirror.json``, docs/models.md "The sea surface").

The worker that runs BELLHOP reduces the arrivals at once (``image_tl_db``), so what travels back
and is cached is one small array per run: TL (class, band, receiver depth, range).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import numpy as np

from acoustics.bellhop.arrfile import Arrivals


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

    @property
    def digest(self) -> str:
        """A hash of everything the reduction uses (part of the run's key)."""
        h = hashlib.sha256(repr((self.receiver_depth_m, self.speed_mps, self.tl_max_db)).encode())
        for row in self.bands:
            for b in row:
                for a in (b.freqs_hz, b.attenuation_ratio, b.weights):
                    h.update(repr(a.shape).encode())
                    h.update(np.ascontiguousarray(a, dtype=np.float64).tobytes())
        return h.hexdigest()


def image_tl_db(arrivals: Arrivals, image: SurfaceImage) -> np.ndarray:
    """Band TL at the run's rows with the surface at their end, ``(class, band, row, range)``,
    float32, dB (``tl_max_db`` where nothing arrives): at each row z the arrivals at z and at -z
    of the mirrored run, each with its Lloyd factor band-averaged with the class's spectrum and
    the volume attenuation across the band (the module's formula)."""
    lloyd, _ = image_sums(arrivals, image)
    return intensity_tl_db(lloyd, image.tl_max_db).astype(np.float32)


def intensity_tl_db(intensity, tl_max_db: float) -> np.ndarray:
    """TL = -10 lg I, dB, of a band intensity (`image_sums`), capped at ``tl_max_db`` where
    nothing arrives."""
    return -10.0 * np.log10(np.maximum(intensity, 10.0 ** (-tl_max_db / 10.0)))


def image_sums(arrivals: Arrivals, image: SurfaceImage, *, plain: bool = False
               ) -> tuple[np.ndarray, np.ndarray | None]:
    """The band intensities of `image_tl_db` before the logarithm, ``(class, band, row, range)``:
    with the Lloyd factor, and with ``plain`` also without it (the same arrivals summed
    incoherently; None otherwise)."""
    depths = np.asarray(arrivals.receiver_depth_m, dtype=float)
    nr = arrivals.count.shape[1]
    offsets = np.concatenate([[0], np.cumsum(arrivals.count.ravel())]).astype(np.int64)
    n_class = len(image.bands[0][0].weights) if image.bands and image.bands[0] else 0
    n_band = len(image.bands[0]) if image.bands else 0
    lloyd_sum = np.zeros((n_class, n_band, len(image.receiver_depth_m), nr))
    plain_sum = np.zeros_like(lloyd_sum) if plain else None
    for iz, (z, c) in enumerate(zip(image.receiver_depth_m, image.speed_mps)):
        at_z = (z, -z) if z > 0.0 else (z,)
        mirror = [int(np.flatnonzero(np.isclose(depths, d, rtol=0.0, atol=1e-6))[0]) for d in at_z]
        spans = [slice(offsets[q * nr], offsets[(q + 1) * nr]) for q in mirror]
        amplitude2 = np.concatenate([arrivals.amplitude[s] for s in spans]) ** 2
        attenuation = np.exp(2.0 * 2.0 * np.pi * arrivals.freq_hz
                             * np.concatenate([arrivals.delay_imag_s[s] for s in spans]))
        angle = np.concatenate([arrivals.receiver_angle_deg[s] for s in spans])
        at_range = np.concatenate([np.repeat(np.arange(nr), arrivals.count[q]) for q in mirror])
        depth, speed = np.full(angle.size, float(z)), np.full(angle.size, float(c))
        for ib, band in enumerate(image.bands[iz]):
            flat, lloyd = _band_sums(attenuation, depth, speed, angle, band)
            for ic in range(n_class):
                lloyd_sum[ic, ib, iz] = np.bincount(at_range, weights=amplitude2 * lloyd[ic], minlength=nr)
                if plain:
                    plain_sum[ic, ib, iz] = np.bincount(at_range, weights=amplitude2 * flat[ic], minlength=nr)
    return lloyd_sum, plain_sum


def _band_sums(attenuation, depth, speed, angle_deg, band: ImageBand) -> tuple[np.ndarray, np.ndarray]:
    """Each arrival's band averages per class (``acoustics.builder._lloyd``, numba)."""
    from acoustics.builder._lloyd import band_sums  # compiled on first use, in the worker

    def arr(x):
        return np.ascontiguousarray(x, dtype=np.float64)

    return band_sums(arr(attenuation), arr(depth), arr(speed), arr(angle_deg), band.freqs_hz,
                     band.attenuation_ratio, band.weights)
