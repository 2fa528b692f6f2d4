"""Weights of an atlas's positions around observer positions: how tables are mixed between them.

README "Atlases": between positions the tables are interpolated in dB. On a lattice the four
nodes around the observer are weighted bilinearly in (row, column); where one of them has no
table (left out: land, shallow water), the observer is weighted barycentrically over the other
three if it lies in their triangle. Listed positions are triangulated (Delaunay, in the
azimuthal equidistant plane about the area's origin) and the observer weighted barycentrically
over the triangle around it. An observer outside (the hull of the positions, or a lattice cell
without tables enough around it) is an error, never an extrapolation.

Those weights are then tempered by the water (`water_weights`): a position whose water is much
deeper or shallower than the observer's counts less, so that an observer on a slope is not
given the tables of a shelf position beside it (on a 10 km lattice across a shelf break, one
cell holds 175 m and 1375 m of water; docs/atlas-tracking.md). Where the positions around have
the observer's depth, the weights are the bilinear (barycentric) ones.
"""

from __future__ import annotations

import math

import numpy as np

from acoustics.errors import ObserverPositionError
from envdata.errors import InputError

#: A weight this far below 0 still counts as inside a triangle (rounding).
INSIDE_TOLERANCE = 1e-9
#: A position whose water is this many times as deep (or as shallow) as the observer's keeps
#: e^-1/2 of its weight (`water_weights`). Chosen on the follow study (docs/atlas-tracking.md,
#: docs/results/atlas-tracking/blend.json): with 2 the K along the path was closer still, but
#: the particle filter lost more runs on the flatter K(r); with 3 both trackers gained.
WATER_DEPTH_RATIO = 3.0


def lattice_weights(lat_deg, lon_deg, lattice: dict, node_origin: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Origins (P, 4) and weights (P, 4) around observers on a lattice.

    Parameters
    ----------
    lat_deg, lon_deg : array_like, shape (P,)
        Observer positions, deg.
    lattice : dict
        ``lat0_deg, lon0_deg, dlat_deg, dlon_deg, rows, cols``.
    node_origin : ndarray, shape (rows, cols)
        The origin index of each node, -1 where it has no table.

    Raises
    ------
    ObserverPositionError
        An observer outside the lattice, or in a cell without three tables around it: the first
        such observer (``index``, its place in the input, from 0).
    """
    lat = np.atleast_1d(np.asarray(lat_deg, dtype=float))
    lon = np.atleast_1d(np.asarray(lon_deg, dtype=float))
    rows, cols = int(lattice["rows"]), int(lattice["cols"])
    fr = (lat - lattice["lat0_deg"]) / lattice["dlat_deg"]
    fc = (lon - lattice["lon0_deg"]) / lattice["dlon_deg"]
    eps = 1e-9
    outside = (fr < -eps) | (fr > rows - 1 + eps) | (fc < -eps) | (fc > cols - 1 + eps) | ~np.isfinite(fr + fc)
    if outside.any():
        i = int(np.argmax(outside))
        raise ObserverPositionError(i, f"{lat[i]:.5f} N {lon[i]:.5f} E is outside the atlas's lattice")
    r0 = np.clip(np.floor(fr), 0, max(rows - 2, 0)).astype(int)
    c0 = np.clip(np.floor(fc), 0, max(cols - 2, 0)).astype(int)
    tr = np.clip(fr - r0, 0.0, 1.0) if rows > 1 else np.zeros_like(fr)
    tc = np.clip(fc - c0, 0.0, 1.0) if cols > 1 else np.zeros_like(fc)
    r1 = np.minimum(r0 + 1, rows - 1)
    c1 = np.minimum(c0 + 1, cols - 1)
    idx = np.stack([node_origin[r0, c0], node_origin[r0, c1], node_origin[r1, c0], node_origin[r1, c1]], axis=1)
    w = np.stack([(1 - tr) * (1 - tc), (1 - tr) * tc, tr * (1 - tc), tr * tc], axis=1)
    corner_rc = np.stack([np.stack([r0, c0], 1), np.stack([r0, c1], 1), np.stack([r1, c0], 1),
                          np.stack([r1, c1], 1)], axis=1).astype(float)  # (P, 4, 2)
    missing = (idx < 0) & (w > eps)
    for p in np.flatnonzero(missing.any(axis=1)):
        have = np.flatnonzero(idx[p] >= 0)
        lam = None
        if have.size == 3:
            lam = _barycentric(corner_rc[p, have], np.array([fr[p], fc[p]]))
        if lam is None or lam.min() < -INSIDE_TOLERANCE:
            raise ObserverPositionError(int(p), f"{lat[p]:.5f} N {lon[p]:.5f} E is not surrounded by the atlas's "
                                        f"tables (a lattice node next to it was left out: land or shallow water)")
        w[p] = 0.0
        w[p, have] = np.clip(lam, 0.0, None)
    idx = np.where(w > 0, idx, np.maximum(idx, 0))  # a corner of no weight: any valid index
    idx = np.where(idx < 0, 0, idx)
    return idx, w


def water_weights(w: np.ndarray, position_depth_m: np.ndarray, observer_depth_m: np.ndarray,
                  ratio: float = WATER_DEPTH_RATIO) -> np.ndarray:
    """Weights (P, K) of positions around observers tempered by how alike their water is.

    Each weight is multiplied by ``exp(-0.5 (ln(h_position / h_observer) / ln(ratio))^2)`` and
    the row renormalised: positions of the observer's depth keep their share, one ``ratio``
    times as deep or as shallow e^-1/2 of it. A row whose depths are not all known and positive
    (a position without a bottom, an observer's depth that could not be read) is left as it is.

    Parameters
    ----------
    w : ndarray, shape (P, K)
        Bilinear or barycentric weights, rows summing to 1.
    position_depth_m : ndarray, shape (P, K)
        The water depth at each of those positions, m.
    observer_depth_m : ndarray, shape (P,)
        The water depth at each observer, m.
    ratio : float
        > 1.
    """
    h = np.asarray(position_depth_m, dtype=float)
    ho = np.asarray(observer_depth_m, dtype=float)
    counted = w > 0
    known = np.all(~counted | (np.isfinite(h) & (h > 0)), axis=1) & np.isfinite(ho) & (ho > 0)
    out = np.array(w, dtype=float)
    if known.any():
        x = np.log(np.where(counted[known], h[known], 1.0) / ho[known, None]) / math.log(ratio)
        tempered = w[known] * np.exp(-0.5 * x ** 2)
        out[known] = tempered / tempered.sum(axis=1, keepdims=True)
    return out


def _barycentric(tri: np.ndarray, point: np.ndarray) -> np.ndarray | None:
    """Barycentric coordinates of ``point`` in triangle ``tri`` (3, 2); None if degenerate."""
    a, b, c = tri
    m = np.array([[b[0] - a[0], c[0] - a[0]], [b[1] - a[1], c[1] - a[1]]])
    det = np.linalg.det(m)
    if abs(det) < 1e-12:
        return None
    l1, l2 = np.linalg.solve(m, point - a)
    return np.array([1.0 - l1 - l2, l1, l2])


def listed_weights(x_m, y_m, pos_x_m: np.ndarray, pos_y_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Origins (P, 3) and barycentric weights (P, 3) over the Delaunay triangle around each
    observer (plane coordinates, m).

    Raises
    ------
    InputError
        Fewer than three positions not on a line; ``ObserverPositionError``, an observer outside
        their hull.
    """
    from matplotlib.tri import Triangulation

    x = np.atleast_1d(np.asarray(x_m, dtype=float))
    y = np.atleast_1d(np.asarray(y_m, dtype=float))
    if pos_x_m.size < 3:
        raise InputError(f"the atlas has {pos_x_m.size} position(s): between positions it needs three or more")
    try:
        tri = Triangulation(pos_x_m, pos_y_m)
    except (ValueError, RuntimeError) as exc:
        raise InputError(f"the atlas's positions cannot be triangulated ({exc})") from None
    found = tri.get_trifinder()(x, y)
    if (found < 0).any():
        i = int(np.argmax(found < 0))
        raise ObserverPositionError(i, f"({x[i]:.0f} m, {y[i]:.0f} m) from the origin is outside the hull of "
                                       f"the atlas's positions")
    idx = tri.triangles[found]  # (P, 3)
    w = np.empty(idx.shape)
    for p in range(x.size):
        lam = _barycentric(np.stack([pos_x_m[idx[p]], pos_y_m[idx[p]]], axis=1), np.array([x[p], y[p]]))
        w[p] = np.clip(lam, 0.0, None)
    return idx, w / w.sum(axis=1, keepdims=True)
