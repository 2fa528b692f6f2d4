"""The coverage map of an atlas: at every position, a class's detection range (or K at a range),
over the water depth the atlas's radials sampled.

Each position's value is the median over its radials: the detection range of the class at its
mean level (``acoustics.grid.detectionmap``, in one band or any band), or K(r) at ``range_m``
in one band. Positions left out (land, shallow water) are marked with a cross; a position whose
median detection range is the table's last range is ringed: the table ends there, not detection
(``--what pd`` says how far it goes, ``acoustics.plots.atlaspd``).
"""

from __future__ import annotations

from enum import StrEnum

import numpy as np

from acoustics.grid.atlas.store import AtlasStore
from acoustics.grid.detectionmap import detection_map
from acoustics.plots.figures import new_figure
from envdata.errors import InputError
from envdata.radials import geodesic_points


class AtlasWhat(StrEnum):
    DETECTION = "detection"
    K = "k"


def coverage_values(store: AtlasStore, *, what: AtlasWhat, cls_name: str, band: str | None, month: int,
                    range_m: float | None) -> np.ndarray:
    """The map's value at every position (NaN where the table is not built), km or dB."""
    m = store.month_index(month)
    out = np.full(store.lat_deg.size, np.nan)
    for o in range(store.lat_deg.size):
        if not store.done[m, o]:
            continue
        tables = store.sel(month=month, origin=o)
        if what is AtlasWhat.DETECTION:
            dm = detection_map(tables, cls_name, store.bearing_deg)
            ranges = dm.range_m if band is None else dm.band_range_m[tables.band_index(band)]
            out[o] = np.nanmedian(np.where(np.isfinite(ranges), ranges, 0.0)) / 1000.0
        else:
            ib = tables.band_index(band) if band is not None else 0
            k = tables.k_at(tables.class_index(cls_name), np.full(store.bearing_deg.size, range_m),
                            bearing_deg=store.bearing_deg)[ib]
            out[o] = np.nanmedian(k) if np.isfinite(k).any() else np.nan
    return out


def draw_atlas_relief(ax, store: AtlasStore, *, colorbar: bool = True) -> None:
    """The water depth where the atlas's radials sampled it (from the tables of the first month),
    filled contours on latitude-longitude axes."""
    lats, lons, depths = [], [], []
    for o in range(store.lat_deg.size):
        if not store.done[0, o]:
            continue
        bottom = store.slab(0, o)[2]
        for j, bearing in enumerate(store.bearing_deg):
            la, lo = geodesic_points(store.lat_deg[o], store.lon_deg[o], bearing, store.range_m)
            lats.append(la)
            lons.append(lo)
            depths.append(bottom[j])
    if lats:
        la, lo, d = np.concatenate(lats), np.concatenate(lons), np.concatenate(depths)
        wet = np.isfinite(d)
        if wet.sum() >= 3:
            cf = ax.tricontourf(lo[wet], la[wet], d[wet], levels=12, cmap="Blues")
            if colorbar:
                ax.figure.colorbar(cf, ax=ax, label="water depth, m", shrink=0.8)


def coverage_figure(store: AtlasStore, *, what: AtlasWhat | str = AtlasWhat.DETECTION, cls_name: str | None = None,
                    band: str | None = None, month: int | None = None, range_m: float | None = None):
    """The coverage map (a ``Figure``). Raises InputError for a class, band or month not in the atlas."""
    what = AtlasWhat(what)
    cls_name = cls_name if cls_name is not None else store.class_names[0]
    if cls_name not in store.class_names:
        raise InputError(f"{store.path}: class {cls_name!r} is not in the atlas ({', '.join(store.class_names)})")
    if band is not None and band not in store.band_names:
        raise InputError(f"{store.path}: band {band!r} is not in the atlas ({', '.join(store.band_names)})")
    month = int(store.months[0]) if month is None else month
    store.month_index(month)
    if what is AtlasWhat.K:
        range_m = float(store.range_m[store.range_m.size // 2]) if range_m is None else range_m
        if not store.range_m[0] <= range_m <= store.range_m[-1]:
            raise InputError(f"{store.path}: range {range_m / 1000:g} km is outside the tables' "
                             f"{store.range_m[0] / 1000:g}-{store.range_m[-1] / 1000:g} km")
    values = coverage_values(store, what=what, cls_name=cls_name, band=band, month=month, range_m=range_m)
    fig = new_figure(figsize=(7.5, 6.0), layout="constrained")
    ax = fig.add_subplot()
    draw_atlas_relief(ax, store)
    label = (f"median detection range of {cls_name} ({band or 'any band'}), km" if what is AtlasWhat.DETECTION
             else f"median K of {cls_name} in {band or store.band_names[0]} at {range_m / 1000:g} km, dB")
    sc = ax.scatter(store.lon_deg, store.lat_deg, c=values, s=120, cmap="viridis", edgecolors="k", zorder=3)
    fig.colorbar(sc, ax=ax, label=label, shrink=0.8)
    if what is AtlasWhat.DETECTION:
        # a median at the table's last range is the table's edge, not where detection ends
        edge = np.isclose(values, store.range_m[-1] / 1000.0)
        if edge.any():
            ring = ax.scatter(store.lon_deg[edge], store.lat_deg[edge], s=260, facecolors="none",
                              edgecolors="#e7298a", linewidths=2.0, zorder=4,
                              label="at the table's last range: detection may go on (--what pd)")
            ring.set_gid("table-edge")
    if store.left_out:
        ax.scatter([p["lon_deg"] for p in store.left_out], [p["lat_deg"] for p in store.left_out], marker="x",
                   c="0.3", label="left out (land, shallow)", zorder=3)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(loc="lower left", fontsize=8)
    ax.set_xlabel("longitude, deg E")
    ax.set_ylabel("latitude, deg N")
    ax.set_aspect(1.0 / np.cos(np.radians(float(np.mean(store.lat_deg)))))
    ax.set_title(f"atlas {store.area.name}, month {month}: {store.lat_deg.size} positions")
    return fig, values
