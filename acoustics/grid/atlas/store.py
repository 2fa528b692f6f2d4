"""An open atlas store: its area, positions, months and axes, and its tables read on demand.

`open_store(path)` opens a store (docs/formats.md "Atlas (Zarr store)"): it must be tmakit's, of
this version's format, with its stored area (``area_json``) readable; the area is parsed once,
here, and every table's area derived from it. An `AtlasStore` holds the tables and answers
nothing itself: ``store.sel(month=M, origin=i)`` is the bearing-dependent grid face
(``RadialTables``) of that month with ``[origin]`` at position i, ``store.weights_at(x, y)`` the
positions around observers and their weights (``acoustics.grid.atlas.weights``: bilinear on the
lattice, barycentric over a triangle of listed positions, tempered by how alike each position's
water depth is to the observer's, read from the positions' own radials), and the faces that answer between
positions are ``acoustics.grid.atlas.follow``'s (through ``acoustics.open_tables``). A table
whose chunks are missing or fail their checksum is never read as numbers: it counts as not
built, and reading it is an ``AtlasFileError`` naming the command that rebuilds it.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from acoustics.grid.atlas.format import AtlasFileError, check_format, chunk_exists, is_atlas_attrs, read_attrs
from acoustics.grid.atlas.weights import WATER_DEPTH_RATIO, lattice_weights, listed_weights, water_weights
from acoustics.grid.checked import checked_tables
from acoustics.grid.dataset import radial_dataset
from acoustics.grid.lookup import axis_cells, bearing_weights
from acoustics.grid.radialtables import RadialTables
from envdata.area import Area
from envdata.areafile import area_from_json
from envdata.atlasarea import area_for_month, table_area
from envdata.errors import AreaError, InputError
from envdata.geometry import lat_lon_to_local_plane, local_plane_to_lat_lon


@dataclass(eq=False)
class AtlasStore:
    """An open atlas store: its area, positions, months and axes; tables read on demand.

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
    lattice : dict or None
        The lattice's ``lat0_deg, lon0_deg, dlat_deg, dlon_deg, rows, cols`` (None: listed
        positions).
    water_depth_ratio : float or None
        How the positions' water tempers their weights around an observer
        (``weights.water_weights``); None: the bilinear (barycentric) weights alone. Set it
        before any face of the store is asked for tables (they keep their weights).
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
    lattice: dict | None
    _group: object = field(repr=False)
    water_depth_ratio: float | None = WATER_DEPTH_RATIO
    _slabs: dict = field(default_factory=dict, repr=False)
    _k_tables: dict = field(default_factory=dict, repr=False)
    _kept: dict = field(default_factory=dict, repr=False)

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

    def check_table(self, m: int, o: int) -> None:
        """AtlasFileError for a table not built or damaged; InputError for a position not in the atlas."""
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
            self.check_table(m, o)
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
            self.check_table(m, o)
        if missing:
            block = self._read("k_db", (int(m), missing))
            for o, k in zip(missing, block):
                k.setflags(write=False)
                self._k_tables[(int(m), o)] = k
        return [self._slabs[(m, o)][1] if (m, o) in self._slabs else self._k_tables[(m, o)] for o in origins]

    def area_of_month(self, month: int) -> Area:
        """The area with the climatology's ``month`` set (derived once per month, never parsed)."""
        key = ("area", int(month))
        if key not in self._kept:
            self._kept[key] = area_for_month(self.area, int(month))
        return self._kept[key]

    def sel(self, *, month: int, origin: int) -> RadialTables:
        """The bearing-dependent grid of ``month`` with ``[origin]`` at position ``origin``."""
        m = self.month_index(month)
        tl, k, bottom = self.slab(m, origin)
        area_t = table_area(self.area, int(month), self.lat_deg[origin], self.lon_deg[origin])
        ds = radial_dataset(area_t, self.attrs.get("model", "bellhop"), self.attrs.get("source_hash", ""), None,
                            bearing_deg=self.bearing_deg, depth_m=self.depth_m, range_m=self.range_m, tl_db=tl,
                            k_db=k, k_urick_db=self.k_urick_db, bottom_depth_m=bottom,
                            beta_db_per_km=self.beta_db_per_km)
        ds.attrs["title"] = f"table of month {month}, position {origin} of the atlas {self.path.name}"
        return checked_tables(ds, f"{self.path}[month={month}, origin={origin}]", area=area_t)

    def weights(self, lat_deg, lon_deg) -> tuple[np.ndarray, np.ndarray]:
        """The positions around observers at latitudes and longitudes and their weights, (P, 3
        or 4) each; ``ObserverPositionError`` for the first observer outside."""
        lat = np.atleast_1d(np.asarray(lat_deg, dtype=float))
        lon = np.atleast_1d(np.asarray(lon_deg, dtype=float))
        x, y = lat_lon_to_local_plane(*self._plane_origin(), lat, lon)
        if self.lattice is not None:
            return self._tempered(*lattice_weights(lat, lon, self.lattice, self._nodes()), x, y)
        return self.weights_at(x, y)

    def weights_at(self, x_m, y_m) -> tuple[np.ndarray, np.ndarray]:
        """`weights` of observers x east and y north of the area's ``[origin]`` (the local plane of
        the trackers), m: listed positions are weighted in that plane itself, a lattice (rows and
        columns of latitude and longitude) at the observers' latitudes and longitudes; then both
        tempered by the water depth (`observer_water_depth`, ``weights.water_weights``)."""
        x = np.atleast_1d(np.asarray(x_m, dtype=float))
        y = np.atleast_1d(np.asarray(y_m, dtype=float))
        if self.lattice is not None:
            lat, lon = local_plane_to_lat_lon(*self._plane_origin(), x, y)
            return self._tempered(*lattice_weights(lat, lon, self.lattice, self._nodes()), x, y)
        px, py = self.plane_positions()
        return self._tempered(*listed_weights(x, y, px, py), x, y)

    def observer_water_depth(self, idx: np.ndarray, w: np.ndarray, x_m: np.ndarray, y_m: np.ndarray) -> np.ndarray:
        """The water depth at observers (P,), m, read from the atlas itself: each surrounding
        position's bottom along its radials (stored with its table) at the observer's bearing and
        distance from it (linear between the two radials around the bearing and along range), those
        depths weighted by ``w``. NaN where a position's bottom is unknown or not finite there."""
        return self._water_depth(*self._bottoms(idx, w), idx, w, x_m, y_m)

    def _water_depth(self, bottom, slot, idx, w, x_m, y_m) -> np.ndarray:
        """`observer_water_depth` from the positions' bottoms (U, N, R) and each entry's slot."""
        px, py = self.plane_positions()
        dx, dy = x_m[:, None] - px[idx], y_m[:, None] - py[idx]       # (P, K)
        j0, j1, wb = bearing_weights(self.bearing_deg, np.degrees(np.arctan2(dx, dy)))
        r0, r1, wr = axis_cells(np.asarray(self.range_m, dtype=float), np.hypot(dx, dy))
        along = [(1.0 - wr) * bottom[slot, j, r0] + wr * bottom[slot, j, r1] for j in (j0, j1)]
        h = (1.0 - wb) * along[0] + wb * along[1]
        return np.sum(np.where(w > 0, w * h, 0.0), axis=1)

    def _tempered(self, idx: np.ndarray, w: np.ndarray, x_m: np.ndarray, y_m: np.ndarray):
        """``(idx, w)`` with the weights tempered by the water (``weights.water_weights``)."""
        if self.water_depth_ratio is None:
            return idx, w
        bottom, slot = self._bottoms(idx, w)
        h_obs = self._water_depth(bottom, slot, idx, w, x_m, y_m)
        # a position's own depth: its bottom on the ring of its radials' first range (200 m)
        h_pos = bottom[:, :, 0].mean(axis=1)
        return idx, water_weights(w, h_pos[slot], h_obs, self.water_depth_ratio)

    def _bottoms(self, idx: np.ndarray, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The bottoms along their radials (U, N, R), m, of the positions ``idx`` weighs (``w`` >
        0), and each entry's row in them (its slot; any row where its weight is 0). Read from the
        store for the positions not read yet, in one read, and kept. NaN for a position none of
        whose tables is done (its bottom may be missing from the store)."""
        kept = self._kept.setdefault(("bottoms",), {})
        used = np.unique(idx[w > 0])
        missing = [int(o) for o in used if int(o) not in kept]
        if missing:
            block = self._read("bottom_depth_m", missing).astype(float)
            for o, b in zip(missing, block):
                if not self.done[:, o].any():
                    b[...] = np.nan
                b.setflags(write=False)
                kept[o] = b
        bottom = np.stack([kept[int(o)] for o in used])  # every row of weights has a weight > 0
        slot = np.clip(np.searchsorted(used, idx), 0, used.size - 1)
        return bottom, slot

    def plane_positions(self) -> tuple[np.ndarray, np.ndarray]:
        """The positions x east and y north of the area's ``[origin]``, m (kept)."""
        key = ("plane",)
        if key not in self._kept:
            self._kept[key] = tuple(np.asarray(v, dtype=float) for v in
                                    lat_lon_to_local_plane(*self._plane_origin(), self.lat_deg, self.lon_deg))
        return self._kept[key]

    def _plane_origin(self) -> tuple[float, float]:
        origin = self.area.origin
        return float(origin.lat_deg), float(origin.lon_deg)

    def _nodes(self) -> np.ndarray:
        """The origin index of each lattice node, -1 where it has no table (rows, cols)."""
        key = ("nodes",)
        if key not in self._kept:
            nodes = np.full((self.lattice["rows"], self.lattice["cols"]), -1, dtype=np.int64)
            nodes[self.row_col[:, 0], self.row_col[:, 1]] = np.arange(self.lat_deg.size)
            self._kept[key] = nodes
        return self._kept[key]


def open_store(path: str | Path, *, attrs: dict | None = None) -> AtlasStore:
    """Open an atlas store: check it is tmakit's, of this format, and which tables are complete.

    ``attrs``: the store's attributes when the caller has read them (``read_attrs``), so that
    they, ``area_json`` among them, are read once.

    Raises
    ------
    AtlasFileError
        Not a folder, not a tmakit atlas, another format, an unreadable ``area_json``.
    """
    import zarr

    path = Path(path)
    if not path.is_dir():
        raise AtlasFileError(f"{path}: no such atlas (an atlas is a Zarr store, a folder)")
    attrs = read_attrs(path) if attrs is None else attrs
    if not is_atlas_attrs(attrs):
        raise AtlasFileError(f"{path}: not a tmakit atlas (no Zarr 3 group with tmakit_kind = \"atlas\")")
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
    lattice = attrs.get("lattice")
    return AtlasStore(path=path, area=area, attrs=attrs, months=coords["month"].astype(int),
                       lat_deg=coords["origin_lat_deg"], lon_deg=coords["origin_lon_deg"],
                       row_col=np.stack([coords["origin_row"], coords["origin_col"]], axis=1).astype(int),
                       bearing_deg=coords["bearing"], depth_m=coords["depth"], range_m=coords["range"],
                       k_urick_db=coords["k_urick_db"], beta_db_per_km=coords["beta_db_per_km"], done=done,
                       left_out=json.loads(attrs.get("left_out", "[]")),
                       lattice=None if lattice is None else json.loads(lattice), _group=group)
