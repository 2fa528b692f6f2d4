"""The atlas face: the tables of many observer positions and months, read from one Zarr store.

``open_atlas(path)`` is the one way in (docs/formats.md "Atlas (Zarr store)"): the store must be
tmakit's, of this version's format, with its stored area (``area_json``) readable. It returns an
`AtlasTables`, the third geometry of the grid face: ``atlas.sel(month=M, origin=i)`` is the
bearing-dependent grid (`RadialTables`) of that month with ``[origin]`` at position i, and
``atlas.values_at(...)`` gives K and TL at observer positions between the positions
(``acoustics.grid.atlasweights``: bilinear on the lattice, barycentric over a triangle of listed
positions; in dB). A table whose chunks are missing or fail their checksum is never read as
numbers: it counts as not built, and reading it is an ``AtlasFileError`` naming the command that
rebuilds it.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import xarray as xr

from acoustics.grid.atlasstore import AtlasFileError, check_format, chunk_exists, is_atlas_store, read_attrs
from acoustics.grid.atlasweights import lattice_weights, listed_weights
from acoustics.grid.dataset import grid_attrs, grid_coords
from acoustics.grid.radialinterp import bearing_weights
from acoustics.grid.tables import RadialTables, as_tables
from acoustics.kcurve import spectral_term_db
from envdata.area import Area
from envdata.areafile import area_from_json
from envdata.atlasarea import table_area
from envdata.errors import AreaError, InputError


@dataclass(eq=False)
class AtlasTables:
    """An open atlas: its area, positions, months and axes; tables read on demand.

    Attributes
    ----------
    path : Path
    area : Area
        The area file the atlas was built from, ``[atlas]`` included.
    months : ndarray of int, shape (M,)
    lat_deg, lon_deg : ndarray, shape (O,)
        The positions with tables, deg.
    done : ndarray of bool, shape (M, O)
        Tables complete, with every chunk in the store.
    """

    path: Path
    area: Area
    attrs: dict
    months: np.ndarray
    lat_deg: np.ndarray
    lon_deg: np.ndarray
    row_col: np.ndarray
    bearing_deg: np.ndarray
    depth_m: np.ndarray
    range_m: np.ndarray
    k_urick_db: np.ndarray
    beta_db_per_km: np.ndarray
    done: np.ndarray
    left_out: list
    _group: object = field(repr=False)
    _slabs: dict = field(default_factory=dict, repr=False)
    _k_tables: dict = field(default_factory=dict, repr=False)

    @property
    def class_names(self) -> tuple[str, ...]:
        return tuple(c.name for c in self.area.classes)

    @property
    def band_names(self) -> tuple[str, ...]:
        return tuple(b.name for b in self.area.bands)

    def month_index(self, month: int) -> int:
        hits = np.flatnonzero(self.months == month)
        if not hits.size:
            raise InputError(f"{self.path}: month {month} is not in the atlas (months: "
                             f"{', '.join(str(m) for m in self.months)})")
        return int(hits[0])

    def _check_table(self, m: int, o: int) -> None:
        if not 0 <= o < self.lat_deg.size:
            raise InputError(f"{self.path}: origin {o} is not in the atlas (0..{self.lat_deg.size - 1})")
        if not self.done[m, o]:
            raise AtlasFileError(f"{self.path}: the table of month {self.months[m]} at position {o} "
                                 f"({self.lat_deg[o]:.4f} N {self.lon_deg[o]:.4f} E) is not built or is damaged; "
                                 f"tmakit atlas build {self.area.name} rebuilds it")

    def _read(self, name: str, selection) -> np.ndarray:
        try:
            return np.asarray(self._group[name][selection])
        except Exception as exc:  # noqa: BLE001 - a chunk that fails its checksum or does not decode
            raise AtlasFileError(f"{self.path}: {name}: a damaged chunk ({type(exc).__name__}); tmakit atlas "
                                 f"build {self.area.name} rebuilds it") from None

    def slab(self, m: int, o: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The table of (month index, origin index): TL (C, B, N, Z, R), K (C, B, N, R), bottom (N, R).

        Read from the store once (the arrays are kept, read-only, for the next call).
        """
        key = (int(m), int(o))
        if key not in self._slabs:
            self._check_table(m, o)
            arrays = (self._read("tl_db", (m, o)), self._read("k_db", (m, o)), self._read("bottom_depth_m", o))
            for a in arrays:
                a.setflags(write=False)
            self._slabs[key] = arrays
        return self._slabs[key]

    def k_tables(self, m: int, origins) -> list[np.ndarray]:
        """K (C, B, N, R) of the tables of month index ``m`` at positions ``origins``, read alone
        (a particle filter's level model needs no TL; those not kept yet in one read of the
        store), kept read-only like `slab`."""
        origins = [int(o) for o in origins]
        missing = sorted({o for o in origins if (m, o) not in self._slabs and (m, o) not in self._k_tables})
        for o in missing:
            self._check_table(m, o)
        if missing:
            block = self._read("k_db", (int(m), missing))
            for o, k in zip(missing, block):
                k.setflags(write=False)
                self._k_tables[(int(m), o)] = k
        return [self._slabs[(m, o)][1] if (m, o) in self._slabs else self._k_tables[(m, o)] for o in origins]

    def at(self, lat_deg: float, lon_deg: float, month: int) -> RadialTables:
        """The bearing-dependent tables at an observer position between the positions: every value
        of the surrounding positions' tables weighted in dB (``acoustics.grid.atlasfollow.blend``)."""
        from acoustics.grid.atlasfollow import blend

        idx, w = self.weights(np.array([float(lat_deg)]), np.array([float(lon_deg)]))
        return blend(self, int(month), [(int(i), float(v)) for i, v in zip(idx[0], w[0]) if v > 0],
                     float(lat_deg), float(lon_deg))

    def follow(self, month: int | None = None):
        """The grid face the trackers take: the tables of ``month`` around the observer at every
        cycle (``acoustics.grid.atlasfollow.FollowingTables``)."""
        from acoustics.grid.atlasfollow import follow

        return follow(self, month)

    def sel(self, *, month: int, origin: int) -> RadialTables:
        """The bearing-dependent grid of ``month`` with ``[origin]`` at position ``origin``."""
        m = self.month_index(month)
        tl, k, bottom = self.slab(m, origin)
        area_t = table_area(self.area, int(month), self.lat_deg[origin], self.lon_deg[origin])
        coords = grid_coords(area_t, self.depth_m, self.range_m)
        coords["bearing"] = ("bearing", self.bearing_deg, {"units": "degree"})
        dims5 = ("class", "band", "bearing", "depth", "range")
        dims4 = ("class", "band", "bearing", "range")
        ds = xr.Dataset({
            "tl_db": (dims5, tl, {"units": "dB", "fixed_end": "observer"}),
            "k_db": (dims4, k, {"units": "dB"}),
            "k_urick_db": (("class", "band", "range"), self.k_urick_db, {"units": "dB"}),
            "anomaly_db": (dims4, k - self.k_urick_db[:, :, None, :], {"units": "dB"}),
            "bottom_depth_m": (("bearing", "range"), bottom, {"units": "m"}),
            "beta_db_per_km": (("band",), self.beta_db_per_km, {"units": "dB km-1"}),
        }, coords=coords)
        attrs = grid_attrs(area_t, self.attrs.get("model", "bellhop"), self.attrs.get("source_hash", ""), None,
                           water_depth_m=float(self.depth_m[-1]), ssp_interpolation="Q")
        attrs.update(origin_lat_deg=float(self.lat_deg[origin]), origin_lon_deg=float(self.lon_deg[origin]),
                     title=f"table of month {month}, position {origin} of the atlas {self.path.name}")
        ds.attrs.update(attrs)
        return as_tables(ds, f"{self.path}[month={month}, origin={origin}]")

    def weights(self, lat_deg, lon_deg) -> tuple[np.ndarray, np.ndarray]:
        """The positions around observers and their weights, (P, 3 or 4) each."""
        lattice = self.attrs.get("lattice")
        if lattice is not None:
            lat_info = json.loads(lattice)
            nodes = np.full((lat_info["rows"], lat_info["cols"]), -1, dtype=np.int64)
            nodes[self.row_col[:, 0], self.row_col[:, 1]] = np.arange(self.lat_deg.size)
            return lattice_weights(lat_deg, lon_deg, lat_info, nodes)
        from pyproj import Proj

        origin = self.area.origin
        proj = Proj(proj="aeqd", lat_0=origin.lat_deg, lon_0=origin.lon_deg, ellps="WGS84")
        px, py = proj(self.lon_deg, self.lat_deg)
        x, y = proj(np.asarray(lon_deg, dtype=float), np.asarray(lat_deg, dtype=float))
        return listed_weights(x, y, np.asarray(px), np.asarray(py))

    def values_at(self, *, lat_deg, lon_deg, month, cls_name, band_name, bearing_deg, range_m,
                  depth_m=None) -> tuple[np.ndarray, np.ndarray]:
        """K and TL for observers at positions, targets at bearings and ranges from them, dB.

        Parameters
        ----------
        lat_deg, lon_deg : array_like, shape (P,)
            Observer positions, deg.
        month : array_like of int, shape (P,)
        cls_name, band_name : array_like of str, shape (P,)
        bearing_deg, range_m : array_like, shape (P,)
            Where the target is from the observer, deg clockwise from north, m.
        depth_m : array_like, shape (P,), optional
            The target's depth, m; NaN or None: the class's. K is then S - TL at that depth.

        Returns
        -------
        k_db, tl_db : ndarray, shape (P,)
            Each surrounding position's table read at the same bearing and range (linear between
            radials and in range, linear in depth), weighted in dB; NaN below the bottom or
            beyond land at any of them.
        """
        lat = np.atleast_1d(np.asarray(lat_deg, dtype=float))
        n = lat.size
        month = np.broadcast_to(np.asarray(month), (n,))
        cls_arr = np.broadcast_to(np.asarray(cls_name, dtype=object), (n,))
        band_arr = np.broadcast_to(np.asarray(band_name, dtype=object), (n,))
        bearing = np.broadcast_to(np.asarray(bearing_deg, dtype=float), (n,))
        rng = np.broadcast_to(np.asarray(range_m, dtype=float), (n,))
        classes = {c.name: i for i, c in enumerate(self.area.classes)}
        bands = {b.name: i for i, b in enumerate(self.area.bands)}
        for what, arr, names in (("class", cls_arr, classes), ("band", band_arr, bands)):
            bad = [i for i, v in enumerate(arr) if v not in names]
            if bad:
                raise InputError(f"observer {bad[0]}: {what} {arr[bad[0]]!r} is not in the atlas "
                                 f"({', '.join(names)})")
        ci = np.array([classes[v] for v in cls_arr], dtype=int)
        bi = np.array([bands[v] for v in band_arr], dtype=int)
        mi = np.array([self.month_index(int(v)) for v in month], dtype=int) if n else np.zeros(0, int)
        cdepth = np.array([c.depth_m for c in self.area.classes])[ci]
        depth = cdepth if depth_m is None else np.where(np.isfinite(np.broadcast_to(
            np.asarray(depth_m, dtype=float), (n,))), np.asarray(depth_m, dtype=float), cdepth)
        own_k = depth_m is None or ~np.isfinite(np.broadcast_to(np.asarray(depth_m, dtype=float), (n,)))
        own_k = np.broadcast_to(own_k, (n,))
        idx, w = self.weights(lat, np.asarray(lon_deg, dtype=float))
        for p, q in zip(*np.nonzero(w > 0)):
            if not self.done[mi[p], idx[p, q]]:
                self._check_table(mi[p], idx[p, q])
        # every (month, origin) slab needed, read once
        needed = sorted({(int(mi[p]), int(idx[p, q])) for p, q in zip(*np.nonzero(w > 0))})
        slot = {key: s for s, key in enumerate(needed)}
        if needed:
            tls, ks = zip(*[self.slab(m, o)[:2] for m, o in needed])
            tl_all, k_all = np.stack(tls), np.stack(ks)  # (S, C, B, N, Z, R), (S, C, B, N, R)
        j0, j1, wb = bearing_weights(self.bearing_deg, bearing)
        r0, r1, wr = _axis_weights(self.range_m, rng)
        z0, z1, wz = _axis_weights(self.depth_m, depth)
        k_out = np.zeros(n)
        tl_out = np.zeros(n)
        spectral = np.array([[spectral_term_db(c, b) for b in self.area.bands] for c in self.area.classes])
        for q in range(w.shape[1]):
            s = np.array([slot.get((int(mi[p]), int(idx[p, q])), 0) for p in range(n)], dtype=int)
            use = w[:, q] > 0

            def k_of(j, r, s=s):
                return k_all[s, ci, bi, j, r]

            def tl_of(j, z, r, s=s):
                return tl_all[s, ci, bi, j, z, r].astype(float)

            def at_range(fn, *a):
                return (1 - wr) * fn(*a, r0) + wr * fn(*a, r1)

            k_q = (1 - wb) * at_range(k_of, j0) + wb * at_range(k_of, j1) if needed else np.zeros(n)
            tl_q = np.zeros(n)
            if needed:
                for j, wj in ((j0, 1 - wb), (j1, wb)):
                    tl_q += wj * ((1 - wz) * at_range(tl_of, j, z0) + wz * at_range(tl_of, j, z1))
            k_q = np.where(own_k, k_q, spectral[ci, bi] - tl_q)
            k_out += np.where(use, w[:, q] * np.where(use, k_q, 0.0), 0.0)
            tl_out += np.where(use, w[:, q] * np.where(use, tl_q, 0.0), 0.0)
            # a NaN at any position with weight makes the result NaN
            k_out = np.where(use & ~np.isfinite(k_q), np.nan, k_out)
            tl_out = np.where(use & ~np.isfinite(tl_q), np.nan, tl_out)
        return k_out, tl_out


def _axis_weights(axis: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Indices around values on an increasing axis and the weight of the second; the ends held."""
    v = np.clip(values, axis[0], axis[-1])
    i1 = np.clip(np.searchsorted(axis, v, side="left"), 1, max(axis.size - 1, 1)) if axis.size > 1 else \
        np.zeros(v.shape, int)
    i0 = np.maximum(i1 - 1, 0)
    span = axis[i1] - axis[i0]
    w = np.where(span > 0, (v - axis[i0]) / np.where(span > 0, span, 1.0), 0.0)
    return i0, i1, w


def open_atlas(path: str | Path) -> AtlasTables:
    """Open an atlas store: check it is tmakit's, of this format, and which tables are complete.

    Raises
    ------
    AtlasFileError
        Not a folder, not a tmakit atlas, another format, an unreadable ``area_json``.
    """
    import zarr

    path = Path(path)
    if not path.is_dir():
        raise AtlasFileError(f"{path}: no such atlas (an atlas is a Zarr store, a folder)")
    if not is_atlas_store(path):
        raise AtlasFileError(f"{path}: not a tmakit atlas (no Zarr 3 group with tmakit_kind = \"atlas\")")
    attrs = read_attrs(path)
    check_format(path, attrs)
    try:
        area = area_from_json(attrs.get("area_json"), str(path))
    except AreaError as exc:
        raise AtlasFileError(str(exc)) from None
    try:
        group = zarr.open_group(str(path), mode="r", zarr_format=3)
        coords = {name: np.asarray(group[name][...]) for name in
                  ("month", "origin_lat_deg", "origin_lon_deg", "origin_row", "origin_col", "bearing", "depth",
                   "range", "k_urick_db", "beta_db_per_km")}
        done = np.asarray(group["done"][...]) == 1
    except Exception as exc:  # noqa: BLE001 - a missing array or a damaged small chunk
        raise AtlasFileError(f"{path}: not a readable atlas ({type(exc).__name__}: {str(exc)[:120]})") from None
    # a table counts as done only with every chunk of it in the store
    arrays = {name: group[name] for name in ("tl_db", "k_db", "bottom_depth_m")}
    for m, o in zip(*np.nonzero(done)):
        for name, index in (("tl_db", (m, o, 0, 0, 0, 0, 0)), ("k_db", (m, o, 0, 0, 0, 0)),
                            ("bottom_depth_m", (o, 0, 0))):
            if not chunk_exists(path, arrays[name], index):
                done[m, o] = False
                if name == "bottom_depth_m":
                    done[:, o] = False
    if not all(math.isfinite(v) for v in coords["range"]):
        raise AtlasFileError(f"{path}: coordinate 'range' must hold finite numbers")
    return AtlasTables(path=path, area=area, attrs=attrs, months=coords["month"].astype(int),
                       lat_deg=coords["origin_lat_deg"], lon_deg=coords["origin_lon_deg"],
                       row_col=np.stack([coords["origin_row"], coords["origin_col"]], axis=1).astype(int),
                       bearing_deg=coords["bearing"], depth_m=coords["depth"], range_m=coords["range"],
                       k_urick_db=coords["k_urick_db"], beta_db_per_km=coords["beta_db_per_km"], done=done,
                       left_out=json.loads(attrs.get("left_out", "[]")), _group=group)
