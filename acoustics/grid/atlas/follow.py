"""An atlas's tables following the observer: at each cycle, the tables around where it is.

README "Atlases" (docs/formats.md): between an atlas's positions the tables are interpolated in
dB, each surrounding position's table read at the same bearing and range from the observer and
the values weighted bilinearly on the lattice (barycentrically over three listed positions;
``acoustics.grid.atlas.weights``). Weighting every value of the tables by the same weights gives
one table (`blend`): a bearing-dependent face (``RadialTables``, its TL mixed when first asked
for) at the observer's position, so the trackers and the simulator ask it what they ask any grid.

`FollowingTables` is the face the trackers take for an atlas of one month: its own tables are
those at the area's ``[origin]`` (the reference point of the local plane), and
``at_observer(x_m, y_m)`` gives the blended tables at an observer x east and y north of it
(azimuthal equidistant plane, WGS84). The observer stays in that plane: the store weighs its
positions around it there (``AtlasStore.weights_at``; a lattice of latitudes and longitudes
takes the observer's latitude and longitude from it once per position, kept with the weights).
K is blended at once (class x band x bearing x range, a few thousand values); TL (with the depth
axis, a thousand times more) only when asked, for K with the target at another depth. The slabs
of the positions are read from the store once (`AtlasStore.slab` is cached) and the blended
tables of the last few observer positions kept, keyed by the positions and weights: consecutive
cycles share cells, and a tracker and the simulator given the same path get the same tables.
A particle filter asks one class's, one band's K(r) at one bearing per cycle
(``level_profiles_at``): that profile alone is mixed, from the K (not TL) of the 3-4 positions
around the observer on the two radials around the bearing, the same sums in the same order as
the blended tables give it.

Bearings at the observer are taken in the local plane (atan2 of the plane's east and north
differences); against true north at the observer they differ by the meridian convergence,
about 0.01 deg per km east or west of the origin at 43 N, far below the radials' spacing.
"""

from __future__ import annotations

import dataclasses
from collections import OrderedDict
from dataclasses import dataclass, field

import numpy as np

from acoustics.errors import ObserverPositionError
from acoustics.grid.atlas.store import AtlasStore
from acoustics.grid.face import Tables
from acoustics.grid.levelprofile import LevelProfile
from acoustics.grid.lookup import bearing_weights, mix
from acoustics.grid.radialtables import RadialTables, weighted_sum
from envdata.errors import InputError

#: Blended tables kept per following face (the latest observer positions).
VIEW_CACHE = 32
#: Observer positions whose weights are kept per following face.
WEIGHTS_CACHE = 4096
#: Weights are rounded to this in the cache key (a position 1e-6 of a cell apart: the same table).
WEIGHT_KEY_DECIMALS = 6


@dataclass(frozen=True, eq=False, kw_only=True)
class FollowingTables(RadialTables):
    """An atlas of one month as the trackers' face: the tables around the observer.

    Its own tables (what it answers when asked directly) are those at the area's ``[origin]``;
    `at_observer` gives those at another position of the local plane.

    Attributes (beyond ``RadialTables``)
    ------------------------------------
    store : AtlasStore
    month : int
    """

    store: AtlasStore = field(repr=False)
    month: int
    _views: OrderedDict = field(default_factory=OrderedDict, repr=False)
    _weights: dict = field(default_factory=dict, repr=False)

    @property
    def follows_observer(self) -> bool:
        return True

    def observer_offset(self, x_m, y_m):
        return None  # the tables follow the observer

    @property
    def computed_at_one_position(self) -> bool:
        return True  # each position's table, read between positions (`distance_from_origin_m`)

    def distance_from_origin_m(self, x_m, y_m) -> np.ndarray:
        """Each observer position's distance from where the tables it reads were computed, m: the
        mean of its surrounding positions' distances from it, by their weights. The blend reads
        each position's table away from that position, so K's error grows with that distance as
        it does for tables of one position (`acoustics.grid.kerror`), and it is 0 on a position."""
        x, y = np.broadcast_arrays(np.asarray(x_m, dtype=float), np.asarray(y_m, dtype=float))
        px, py = self.store.plane_positions()
        out = [sum(w * float(np.hypot(xi - px[o], yi - py[o])) for o, w in ws) / max(sum(w for _, w in ws), 1e-12)
               for ws, xi, yi in zip(self._weights_at(x.reshape(-1), y.reshape(-1)), x.reshape(-1), y.reshape(-1))]
        return np.asarray(out).reshape(x.shape)

    def check_observers(self, x_m, y_m) -> None:
        self.store.weights_at(np.atleast_1d(x_m), np.atleast_1d(y_m))

    def _weights_at(self, x_m, y_m) -> list[tuple]:
        """Per observer (x east, y north of the origin, m), its positions' (origin index, rounded
        weight): the key of its tables. Weighed once per position (kept), the new ones in one call."""
        xs = np.atleast_1d(np.asarray(x_m, dtype=float))
        ys = np.atleast_1d(np.asarray(y_m, dtype=float))
        points = list(zip(xs.tolist(), ys.tolist()))
        new = list(dict.fromkeys(p for p in points if p not in self._weights))
        if new:
            nx, ny = (np.array(v) for v in zip(*new))
            try:
                idx, w = self.store.weights_at(nx, ny)
            except ObserverPositionError as exc:  # its place among the new -> among those asked
                raise ObserverPositionError(points.index(new[exc.index]), exc.reason) from None
            if len(self._weights) + len(new) > WEIGHTS_CACHE:
                self._weights.clear()
            for p, ip, wp in zip(new, idx, w):
                self._weights[p] = tuple((int(i), round(float(v), WEIGHT_KEY_DECIMALS))
                                         for i, v in zip(ip, wp) if v > 0)
        return [self._weights[p] for p in points]

    def level_profiles_at(self, ic: int, ib: int, x_m, y_m, depth_m, bearing_deg) -> list[LevelProfile]:
        """K(r) of one class and band at one bearing where the observer is each cycle, mixed from
        the K of the positions around it on the two radials around the bearing only (3 or 4
        positions x 2 radials x R values, against every class, band and bearing for
        `at_observer`); the weights of every cycle in one call. The same sums in the same order
        as `blend` then `RadialTables.k_db`: the same numbers, bit for bit. With K at another
        target depth (`at_target_depth`) it goes through `at_observer`."""
        if self.target_depth_m is not None:
            return super().level_profiles_at(ic, ib, x_m, y_m, depth_m, bearing_deg)
        weights = self._weights_at(x_m, y_m)
        keys = [("observer-profile", ws, ic, ib, float(d), self.bearing_key(b))
                for ws, d, b in zip(weights, np.asarray(depth_m, dtype=float), bearing_deg)]
        new = list(dict.fromkeys(k for k in keys if k not in self._cache))
        if new:
            self._cache.update(zip(new, self._mixed_profiles(new)))
        return [self._cache[k] for k in keys]

    def _mixed_profiles(self, keys) -> list[LevelProfile]:
        """The profiles of `level_profiles_at`'s keys, all cycles at once: position by position
        (up to 4, in the key's order), the weighted K of the two radials around each bearing,
        then linear between the radials; a position absent from a key adds nothing."""
        self.check_depth(np.array([k[4] for k in keys]))
        ic, ib = keys[0][2:4]
        m = self.store.month_index(self.month)
        origins = sorted({o for k in keys for o, _ in k[1]})
        k_pos = np.stack([k[ic, ib] for k in self.store.k_tables(m, origins)])  # (O, N, R); new ones in one read
        slot = {o: i for i, o in enumerate(origins)}
        n = max(len(k[1]) for k in keys)
        pos = np.array([[slot[o] for o, _ in k[1]] + [0] * (n - len(k[1])) for k in keys])
        w = np.array([[v for _, v in k[1]] + [0.0] * (n - len(k[1])) for k in keys])
        j0, j1, w1 = bearing_weights(self.bearing_deg, np.array([k[-1] for k in keys]))
        radials = []
        for j in (j0, j1):
            out = w[:, :1] * k_pos[pos[:, 0], j].astype(float)
            for p in range(1, n):
                out = np.where(w[:, p:p + 1] > 0, out + w[:, p:p + 1] * k_pos[pos[:, p], j].astype(float), out)
            radials.append(out)
        k_db = mix(radials[0], radials[1], w1[:, None])
        return [LevelProfile(range_m=self.range_m, k_db=row) for row in k_db]

    def at_observer(self, x_m: float, y_m: float) -> Tables:
        key = (self._weights_at(float(x_m), float(y_m))[0], self.target_depth_m)
        view = self._views.get(key)
        if view is None:
            view = blend(self.store, self.month, [(o, v) for o, v in key[0]], (float(x_m), float(y_m)),
                         dataset=self.dataset)
            if self.target_depth_m is not None:
                view = view.at_target_depth(self.target_depth_m)
            self._views[key] = view
            while len(self._views) > VIEW_CACHE:
                self._views.popitem(last=False)
        else:
            self._views.move_to_end(key)
        return view

    def at_target_depth(self, depth_m: float) -> Tables:
        out = super().at_target_depth(depth_m)
        return dataclasses.replace(out, _views=OrderedDict(), _weights={})


def blend(store: AtlasStore, month: int, weights, where, *, dataset=None) -> RadialTables:
    """The tables at an observer position from its surrounding positions' tables and weights.

    Parameters
    ----------
    store : AtlasStore
    month : int
    weights : sequence of (int, float)
        Positions (origin indices) and their weights, summing to 1.
    where : (float, float)
        The observer's position, x east and y north of the area's origin, m (the blended
        tables' origin, converted to latitude and longitude for their summary).
    dataset : xarray.Dataset, optional
        The dataset the figures draw (default: that of the heaviest position's table).
    """
    from envdata.geometry import local_plane_to_lat_lon

    m = store.month_index(month)
    slabs = [(w, store.slab(m, o)) for o, w in weights]
    heaviest = max(weights, key=lambda ow: ow[1])[0]
    if dataset is None:
        dataset = store.sel(month=month, origin=heaviest).dataset
    area = store.area_of_month(month)
    origin = store.area.origin
    lat_deg, lon_deg = (float(v) for v in local_plane_to_lat_lon(origin.lat_deg, origin.lon_deg, *where))
    return RadialTables(
        source=f"{store.path}[month={month}, {lat_deg:.5f} N {lon_deg:.5f} E]", area=area, dataset=dataset,
        classes=tuple(area.classes), bands=tuple(area.bands), range_m=np.asarray(store.range_m, dtype=float),
        depth_m=np.asarray(store.depth_m, dtype=float), k_grid_db=weighted_sum([(w, s[1]) for w, s in slabs]),
        tl_db=None, observer_depth_m=float(area.observer.depth_m),
        bearing_deg=np.asarray(store.bearing_deg, dtype=float),
        bottom_depth_m=weighted_sum([(w, s[2]) for w, s in slabs]), origin_lat_deg=lat_deg,
        origin_lon_deg=lon_deg, tl_parts=tuple((w, s[0]) for w, s in slabs))


def follow(store: AtlasStore, month: int | None = None) -> FollowingTables:
    """The atlas's tables of ``month`` following the observer (`FollowingTables`).

    ``month`` may be left out when the atlas has one month.

    Raises
    ------
    InputError
        No month given for an atlas of several, a month the atlas lacks, an atlas whose area
        ``[origin]`` is outside its positions.
    """
    if month is None:
        if store.months.size != 1:
            raise InputError(f"{store.path}: the atlas has months {', '.join(str(v) for v in store.months)}: "
                             f"choose one")
        month = int(store.months[0])
    store.month_index(int(month))
    origin = store.area.origin
    try:
        idx, w = store.weights(np.array([origin.lat_deg]), np.array([origin.lon_deg]))
    except ObserverPositionError as exc:
        raise InputError(f"{store.path}: the area's [origin] ({origin.lat_deg:g} N, {origin.lon_deg:g} E), "
                         f"the reference of the local plane, is outside the atlas's positions "
                         f"({exc.reason})") from None
    weights = [(int(i), float(v)) for i, v in zip(idx[0], w[0]) if v > 0]
    base = blend(store, int(month), weights, (0.0, 0.0))
    values = {f.name: getattr(base, f.name) for f in dataclasses.fields(base) if f.name != "_cache"}
    values.update(source=f"{store.path}[month={int(month)}]", origin_lat_deg=float(origin.lat_deg),
                  origin_lon_deg=float(origin.lon_deg))
    return FollowingTables(**values, store=store, month=int(month))


__all__ = ["FollowingTables", "blend", "follow"]
