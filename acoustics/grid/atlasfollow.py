"""An atlas's tables following the observer: at each cycle, the tables around where it is.

README "Atlases" (docs/formats.md): between an atlas's positions the tables are interpolated in
dB, each surrounding position's table read at the same bearing and range from the observer and
the values weighted bilinearly on the lattice (barycentrically over three listed positions;
``acoustics.grid.atlasweights``). Weighting every value of the tables by the same weights gives
one table, `BlendedTables`: a bearing-dependent grid face (`RadialTables`) at the observer's
position, so the trackers and the simulator ask it what they ask any grid.

`FollowingTables` is the face the trackers take for an atlas of one month: its own tables are
those at the area's ``[origin]`` (the reference point of the local plane), and
``at_observer(x_m, y_m)`` gives the blended tables at an observer x east and y north of it
(azimuthal equidistant plane, WGS84). K is blended at once (class x band x bearing x range, a
few thousand values); TL (with the depth axis, a thousand times more) only when asked, for K
with the target at another depth. The slabs of the positions are read from the store once
(`AtlasTables.slab` is cached) and the blended tables of the last few observer positions kept,
keyed by the positions and weights: consecutive cycles share cells, and a tracker and the
simulator given the same path get the same tables. A particle filter asks one class's, one
band's K(r) at one bearing per cycle (``level_profiles_at``): that profile alone is mixed, from
the K (not TL) of the 3-4 positions around the observer on the two radials around the bearing,
the same sums in the same order as the blended tables give it.

Bearings at the observer are taken in the local plane (atan2 of the plane's east and north
differences); against true north at the observer they differ by the meridian convergence,
about 0.01 deg per km east or west of the origin at 43 N, far below the radials' spacing.
"""

from __future__ import annotations

import dataclasses
from collections import OrderedDict
from dataclasses import dataclass, field

import numpy as np

from acoustics.grid.radialinterp import bearing_weights, mix
from acoustics.grid.tables import GridTables, LevelProfile, RadialTables
from envdata.atlasarea import area_for_month
from envdata.errors import InputError
from envdata.geometry import local_plane_to_lat_lon

#: Blended tables kept per following face (the latest observer positions).
VIEW_CACHE = 32
#: Weights are rounded to this in the cache key (a position 1e-6 of a cell apart: the same table).
WEIGHT_KEY_DECIMALS = 6


@dataclass(frozen=True, eq=False, kw_only=True)
class BlendedTables(RadialTables):
    """Bearing-dependent tables mixed in dB from an atlas's positions around one observer position.

    Attributes (beyond `RadialTables`)
    ----------------------------------
    tl_parts : tuple of (float, ndarray)
        Weights and TL slabs (C, M, N, D, R), float32, of the positions mixed; ``tl_db`` is None
        and the weighted TL is formed the first time it is asked for.
    """

    tl_parts: tuple = ()

    def _observer_tl_db(self) -> np.ndarray:
        key = ("blended-tl",)
        if key not in self._cache:
            self._cache[key] = _weighted([(w, tl) for w, tl in self.tl_parts])
        return self._cache[key]


@dataclass(frozen=True, eq=False, kw_only=True)
class FollowingTables(BlendedTables):
    """An atlas of one month as the trackers' grid face: the tables around the observer.

    Its own tables (what it answers when asked directly) are those at the area's ``[origin]``;
    `at_observer` gives those at another position of the local plane.

    Attributes (beyond `BlendedTables`)
    -----------------------------------
    atlas : acoustics.grid.atlas.AtlasTables
    month : int
    """

    atlas: object = field(repr=False)
    month: int
    _views: OrderedDict = field(default_factory=OrderedDict, repr=False)

    @property
    def follows_observer(self) -> bool:
        return True

    def observer_offset(self, x_m, y_m):
        return None  # the tables follow the observer

    def _plane_to_lat_lon(self, x_m, y_m):
        origin = self.area.origin
        return local_plane_to_lat_lon(origin.lat_deg, origin.lon_deg, x_m, y_m)

    def check_observers(self, x_m, y_m) -> None:
        lat, lon = self._plane_to_lat_lon(np.atleast_1d(x_m), np.atleast_1d(y_m))
        self.atlas.weights(np.atleast_1d(lat), np.atleast_1d(lon))

    def _weights_at(self, x_m, y_m):
        """The observers' latitudes, longitudes and, per observer, its positions' (origin index,
        rounded weight): the key of its tables."""
        lat, lon = self._plane_to_lat_lon(np.atleast_1d(np.asarray(x_m, dtype=float)),
                                          np.atleast_1d(np.asarray(y_m, dtype=float)))
        idx, w = self.atlas.weights(np.atleast_1d(lat), np.atleast_1d(lon))
        keys = [tuple((int(i), round(float(v), WEIGHT_KEY_DECIMALS)) for i, v in zip(ip, wp) if v > 0)
                for ip, wp in zip(idx, w)]
        return np.atleast_1d(lat), np.atleast_1d(lon), keys

    def level_profile_at(self, ic: int, ib: int, x_m: float, y_m: float, depth_m: float | None = None,
                         bearing_deg: float | None = None) -> LevelProfile:
        if self.target_depth_m is not None:
            return self.at_observer(x_m, y_m).level_profile(ic, ib, depth_m, bearing_deg)
        return self.level_profiles_at(ic, ib, [x_m], [y_m], [self.observer_depth_m if depth_m is None else depth_m],
                                      [bearing_deg])[0]

    def level_profiles_at(self, ic: int, ib: int, x_m, y_m, depth_m, bearing_deg) -> list[LevelProfile]:
        """K(r) of one class and band at one bearing where the observer is each cycle, mixed from
        the K of the positions around it on the two radials around the bearing only (3 or 4
        positions x 2 radials x R values, against every class, band and bearing for
        `at_observer`); the weights of every cycle in one call. The same sums in the same order
        as `blend` then `RadialTables.k_db`: the same numbers, bit for bit. With K at another
        target depth (`at_target_depth`) it goes through `at_observer`."""
        if self.target_depth_m is not None:
            return super().level_profiles_at(ic, ib, x_m, y_m, depth_m, bearing_deg)
        _, _, weights = self._weights_at(x_m, y_m)
        keys = [("observer-profile", ws, ic, ib, float(d), self._bearing_key(b))
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
        m = self.atlas.month_index(self.month)
        origins = sorted({o for k in keys for o, _ in k[1]})
        k_pos = np.stack([k[ic, ib] for k in self.atlas.k_tables(m, origins)])  # (O, N, R); new ones in one read
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

    def at_observer(self, x_m: float, y_m: float) -> GridTables:
        lat, lon, weights = self._weights_at(float(x_m), float(y_m))
        key = (weights[0], self.target_depth_m)
        view = self._views.get(key)
        if view is None:
            view = blend(self.atlas, self.month, [(o, v) for o, v in key[0]], float(lat[0]), float(lon[0]),
                         dataset=self.dataset)
            if self.target_depth_m is not None:
                view = view.at_target_depth(self.target_depth_m)
            self._views[key] = view
            while len(self._views) > VIEW_CACHE:
                self._views.popitem(last=False)
        else:
            self._views.move_to_end(key)
        return view

    def at_target_depth(self, depth_m: float) -> GridTables:
        out = super().at_target_depth(depth_m)
        return dataclasses.replace(out, _views=OrderedDict())


def _weighted(parts) -> np.ndarray:
    """The weighted sum of arrays, float64 (NaN where any array of weight > 0 is NaN)."""
    out = None
    for w, a in parts:
        term = w * np.asarray(a, dtype=float)
        out = term if out is None else out + term
    return out


def blend(atlas, month: int, weights, lat_deg: float, lon_deg: float, *, dataset=None) -> BlendedTables:
    """The tables at an observer position from its surrounding positions' tables and weights.

    Parameters
    ----------
    atlas : acoustics.grid.atlas.AtlasTables
    month : int
    weights : sequence of (int, float)
        Positions (origin indices) and their weights, summing to 1.
    lat_deg, lon_deg : float
        The observer's position (the blended tables' origin), deg.
    dataset : xarray.Dataset, optional
        The dataset the figures draw (default: that of the heaviest position's table).
    """
    m = atlas.month_index(month)
    slabs = [(w, atlas.slab(m, o)) for o, w in weights]
    heaviest = max(weights, key=lambda ow: ow[1])[0]
    if dataset is None:
        dataset = atlas.sel(month=month, origin=heaviest).dataset
    area = area_for_month(atlas.area, month)
    bottom = _weighted([(w, s[2]) for w, s in slabs])
    return BlendedTables(
        source=f"{atlas.path}[month={month}, {lat_deg:.5f} N {lon_deg:.5f} E]", area=area, dataset=dataset,
        classes=tuple(area.classes), bands=tuple(area.bands), range_m=np.asarray(atlas.range_m, dtype=float),
        depth_m=np.asarray(atlas.depth_m, dtype=float), k_grid_db=_weighted([(w, s[1]) for w, s in slabs]),
        tl_db=None, observer_depth_m=float(area.observer.depth_m),
        bearing_deg=np.asarray(atlas.bearing_deg, dtype=float), bottom_depth_m=bottom,
        origin_lat_deg=float(lat_deg), origin_lon_deg=float(lon_deg),
        tl_parts=tuple((w, s[0]) for w, s in slabs))


def follow(atlas, month: int | None = None) -> FollowingTables:
    """The atlas's tables of ``month`` following the observer (`FollowingTables`).

    ``month`` may be left out when the atlas has one month.

    Raises
    ------
    InputError
        No month given for an atlas of several, a month the atlas lacks, an atlas whose area
        ``[origin]`` is outside its positions.
    """
    if month is None:
        if atlas.months.size != 1:
            raise InputError(f"{atlas.path}: the atlas has months {', '.join(str(v) for v in atlas.months)}: "
                             f"choose one")
        month = int(atlas.months[0])
    atlas.month_index(int(month))
    origin = atlas.area.origin
    try:
        idx, w = atlas.weights(np.array([origin.lat_deg]), np.array([origin.lon_deg]))
    except InputError as exc:
        raise InputError(f"{atlas.path}: the area's [origin] ({origin.lat_deg:g} N, {origin.lon_deg:g} E), "
                         f"the reference of the local plane, is outside the atlas's positions "
                         f"({str(exc).partition(': ')[2]})") from None
    weights = [(int(i), float(v)) for i, v in zip(idx[0], w[0]) if v > 0]
    base = blend(atlas, int(month), weights, origin.lat_deg, origin.lon_deg)
    values = {f.name: getattr(base, f.name) for f in dataclasses.fields(base) if f.name != "_cache"}
    values["source"] = f"{atlas.path}[month={int(month)}]"
    return FollowingTables(**values, atlas=atlas, month=int(month))


__all__ = ["BlendedTables", "FollowingTables", "blend", "follow"]
