"""Where a fix can lie when each bearing errs by at most +-D_alpha (Schmidt et al., eqs. 24-28).

With bearing errors uniform in [-D_alpha, D_alpha] the crossing of two bearings lies in the
quadrilateral bounded by the extreme bearing lines alpha +- D_alpha (the paper's Fig. 7), whose
diagonals follow eqs. 25-28 (`error_region`). For n bearings the target lies in the
intersection of the n wedges alpha_k +- D_alpha (`error_polygon`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from tracker.errors import LocateError
from tracker.locate.geometry import SAME_POSITION_M, bearing_to_deg, crossing_point, wrap_deg


@dataclass(frozen=True, slots=True, kw_only=True)
class ErrorRegion:
    """The quadrilateral that holds a two-bearing fix when each bearing error is within +-D_alpha.

    Its sides lie on the extreme bearing lines alpha_n +- D_alpha and alpha_{n+1} +- D_alpha
    (the paper's Fig. 7). Vertex k is the crossing of alpha_n + e1 and alpha_{n+1} + e2 with
    (e1, e2) = (+D, +D), (+D, -D), (-D, -D), (-D, +D) for k = 1..4, so that 1-3 is the short
    diagonal (both errors alike: the bearing difference is unchanged) and 2-4 the long one.

    Attributes
    ----------
    vertices_m : ndarray, shape (4, 2)
        Vertices 1-4, (x, y) in m, in order around the quadrilateral.
    d13_m, d13_eq25_m : float
        Short diagonal from the vertices, and by eq. 25, m.
    d24_m, d24_eq26_m, d24_eq27_m : float
        Long diagonal from the exact geometry (the vertices), and by eqs. 26 and 27, m.
    ratio, ratio_eq28 : float
        d24 / d13 from the vertices, and 2 / sin(alpha_n - alpha_{n+1}) (eq. 28).
    area_m2 : float
        Area of the quadrilateral (shoelace formula), m^2.
    area_diagonals_m2 : float
        d13 d24 / 2, the area were the diagonals perpendicular, m^2.
    d_alpha_deg : float
        Bearing error bound D_alpha, deg.
    delta_deg : float
        alpha_n - alpha_{n+1} (wrapped to [-180, 180)), deg.
    baseline_m : float
        Distance between the two observer positions (VT), m.
    """

    vertices_m: np.ndarray
    d13_m: float
    d13_eq25_m: float
    d24_m: float
    d24_eq26_m: float
    d24_eq27_m: float
    ratio: float
    ratio_eq28: float
    area_m2: float
    area_diagonals_m2: float
    d_alpha_deg: float
    delta_deg: float
    baseline_m: float

    def contains(self, x_m, y_m, *, tol_m: float = 1e-9) -> np.ndarray:
        """Whether points lie inside (or within ``tol_m`` of) the convex quadrilateral."""
        return _inside_convex(self.vertices_m, x_m, y_m, tol_m)


def _inside_convex(vertices: np.ndarray, x_m, y_m, tol_m: float) -> np.ndarray:
    x = np.asarray(x_m, dtype=float)[..., None]
    y = np.asarray(y_m, dtype=float)[..., None]
    v0 = vertices
    v1 = np.roll(vertices, -1, axis=0)
    ex, ey = v1[:, 0] - v0[:, 0], v1[:, 1] - v0[:, 1]
    length = np.hypot(ex, ey)
    cross = (ex * (y - v0[:, 1]) - ey * (x - v0[:, 0])) / length  # signed distance to each side
    orient = np.sign(_shoelace(vertices))
    return np.all(orient * cross >= -tol_m, axis=-1)


def _shoelace(vertices: np.ndarray) -> float:
    x, y = vertices[:, 0], vertices[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def check_d_alpha(d_alpha_deg: float) -> None:
    """Raise `LocateError` unless the bearing error bound D_alpha is in (0, 45) deg."""
    if not (math.isfinite(d_alpha_deg) and 0.0 < d_alpha_deg < 45.0):
        raise LocateError(f"d_alpha_deg: the bearing error bound must be in (0, 45) deg, "
                          f"got {d_alpha_deg} deg")


def error_region(obs_x_m, obs_y_m, x_m: float, y_m: float, *,
                 d_alpha_deg: float) -> ErrorRegion:
    """Quadrilateral of possible two-bearing fixes for bearing errors within +-D_alpha.

    Parameters
    ----------
    obs_x_m, obs_y_m : array_like, shape (2,)
        The two observer positions n and n+1, m.
    x_m, y_m : float
        The target (or its estimate), m; the bearings alpha_n, alpha_{n+1} are those from the
        two positions to it.
    d_alpha_deg : float
        Bound D_alpha of the bearing error, deg, in (0, 45).

    Returns
    -------
    ErrorRegion
        Vertices, diagonals (exact, eqs. 25-27), ratio (eq. 28) and area.

    Raises
    ------
    LocateError
        If the two bearings differ by no more than 2 D_alpha (or are that close to opposite):
        the extreme bearing lines then do not close a quadrilateral.
    """
    check_d_alpha(d_alpha_deg)
    ox = np.asarray(obs_x_m, dtype=float)
    oy = np.asarray(obs_y_m, dtype=float)
    if ox.shape != (2,) or oy.shape != (2,):
        raise LocateError(f"error region: need exactly two observer positions, got "
                          f"{ox.size} and {oy.size}")
    baseline = float(np.hypot(ox[1] - ox[0], oy[1] - oy[0]))
    if baseline < SAME_POSITION_M:
        raise LocateError(f"error region: the two observer positions coincide at "
                          f"({ox[0]:g}, {oy[0]:g}) m")
    a = bearing_to_deg(ox, oy, x_m, y_m)
    delta = float(wrap_deg(a[0] - a[1]))
    d = d_alpha_deg
    errs = np.array([(d, d), (d, -d), (-d, -d), (-d, d)])  # vertices 1..4
    vx, vy, r1, r2, _ = crossing_point(ox[0], oy[0], a[0] + errs[:, 0],
                                       ox[1], oy[1], a[1] + errs[:, 1])
    if not (np.all(np.isfinite(vx)) and np.all(r1 > 0.0) and np.all(r2 > 0.0)):
        raise LocateError(f"error region: the bearings {a[0]:.4g} deg and {a[1]:.4g} deg differ "
                          f"by {abs(delta):.4g} deg, which does not exceed 2 D_alpha = "
                          f"{2 * d:g} deg (or come that close to opposite); the bearing lines "
                          f"+-D_alpha do not close a quadrilateral")
    vertices = np.column_stack([vx, vy])
    d13 = float(np.hypot(*(vertices[0] - vertices[2])))
    d24 = float(np.hypot(*(vertices[1] - vertices[3])))
    sd = abs(math.sin(math.radians(delta)))
    sin_d = math.sin(math.radians(d))
    two_d = math.radians(2.0 * d)
    abs_delta = math.radians(abs(delta))
    return ErrorRegion(
        vertices_m=vertices,
        d13_m=d13,
        d13_eq25_m=2.0 * sin_d * baseline / sd,                                    # eq. 25
        d24_m=d24,
        d24_eq26_m=4.0 * sin_d * baseline
        / (math.sin(abs_delta - two_d) * math.sin(abs_delta + two_d)),            # eq. 26
        d24_eq27_m=4.0 * sin_d * baseline / sd ** 2,                               # eq. 27
        ratio=d24 / d13,
        ratio_eq28=2.0 / sd,                                                       # eq. 28
        area_m2=abs(_shoelace(vertices)),
        area_diagonals_m2=0.5 * d13 * d24,
        d_alpha_deg=float(d),
        delta_deg=delta,
        baseline_m=baseline,
    )


@dataclass(frozen=True, slots=True, kw_only=True)
class ErrorPolygon:
    """Where the target can be if every one of n bearings errs by at most +-D_alpha.

    The intersection of the n wedges alpha_k +- D_alpha around the bearings seen from each
    observer position at the estimate; for two bearings it is the `ErrorRegion` quadrilateral.

    Attributes
    ----------
    vertices_m : ndarray, shape (m, 2)
        Vertices in order, (x, y) in m.
    area_m2 : float
        Area, m^2.
    diameter_m : float
        Largest distance between two vertices, m.
    d_alpha_deg : float
        Bearing error bound, deg.
    """

    vertices_m: np.ndarray
    area_m2: float
    diameter_m: float
    d_alpha_deg: float

    def contains(self, x_m, y_m, *, tol_m: float = 1e-9) -> np.ndarray:
        """Whether points lie inside (or within ``tol_m`` of) the convex polygon."""
        return _inside_convex(self.vertices_m, x_m, y_m, tol_m)


def _clip(poly: np.ndarray, px: float, py: float, nx: float, ny: float) -> np.ndarray:
    """Keep the part of a convex polygon where (p - (px, py)) . (nx, ny) >= 0."""
    if len(poly) == 0:
        return poly
    side = (poly[:, 0] - px) * nx + (poly[:, 1] - py) * ny
    out = []
    for k in range(len(poly)):
        cur, nxt = poly[k], poly[(k + 1) % len(poly)]
        sc, sn = side[k], side[(k + 1) % len(poly)]
        if sc >= 0.0:
            out.append(cur)
        if (sc >= 0.0) != (sn >= 0.0):
            t = sc / (sc - sn)
            out.append(cur + t * (nxt - cur))
    return np.array(out).reshape(-1, 2)


def error_polygon(obs_x_m, obs_y_m, x_m: float, y_m: float, *,
                  d_alpha_deg: float) -> ErrorPolygon:
    """Intersection of the wedges alpha_k +- D_alpha of n bearings (generalises Fig. 7).

    Parameters
    ----------
    obs_x_m, obs_y_m : array_like, shape (n,)
        Observer positions, m.
    x_m, y_m : float
        The target or its estimate, m; the bearings are those seen at it.
    d_alpha_deg : float
        Bearing error bound, deg, in (0, 45).

    Raises
    ------
    LocateError
        If the wedges do not close a bounded region (all bearings within 2 D_alpha of each
        other or of the opposite direction).
    """
    check_d_alpha(d_alpha_deg)
    ox = np.atleast_1d(np.asarray(obs_x_m, dtype=float))
    oy = np.atleast_1d(np.asarray(obs_y_m, dtype=float))
    a = np.radians(bearing_to_deg(ox, oy, x_m, y_m))
    d = math.radians(d_alpha_deg)
    reach = 10.0 * float(np.max(np.hypot(ox - x_m, oy - y_m)))
    box_half = 1000.0 * reach + 1.0
    poly = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float) * box_half
    poly += np.array([x_m, y_m])
    for px, py, ak in zip(ox, oy, a):
        # Left of the line at ak + d and right of the line at ak - d (bearing clockwise from
        # north: the direction (sin, cos) turned by -90 deg points to (-cos, sin)).
        poly = _clip(poly, px, py, -math.cos(ak + d), math.sin(ak + d))
        poly = _clip(poly, px, py, math.cos(ak - d), -math.sin(ak - d))
    if len(poly) < 3 or np.max(np.hypot(poly[:, 0] - x_m, poly[:, 1] - y_m)) > 100.0 * reach:
        raise LocateError(f"error region: the {len(ox)} bearing wedges +-{d_alpha_deg:g} deg do "
                          f"not close a bounded region (the bearings differ by no more than "
                          f"2 D_alpha)")
    diff = poly[:, None, :] - poly[None, :, :]
    return ErrorPolygon(vertices_m=poly, area_m2=abs(_shoelace(poly)),
                        diameter_m=float(np.max(np.hypot(diff[..., 0], diff[..., 1]))),
                        d_alpha_deg=float(d_alpha_deg))
