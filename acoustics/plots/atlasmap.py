"""The coverage map of an atlas: at every position, a class's detection range (or K at a range),
over the water depth the atlas's radials sampled.

Each position's value is the median over its radials: the detection range of the class at its
mean level (``acoustics.grid.detectionmap``, in one band or any band), or K(r) at ``range_m``
in one band. Positions left out (land, shallow water) are marked with a cross.
"""

from __future__ import annotations

from enum import StrEnum

import numpy as np

from acoustics.grid.atlas import AtlasTables
from acoustics.grid.detectionmap import detection_map
from acoustics.plots.figures import new_figure
from envdata.errors import InputError
from envdata.radials import geodesic_points


class AtlasWhat(StrEnum):
    DETECTION = "detection"
    K = "k"


def coverage_values(atlas: AtlasTables, *, what: AtlasWhat, cls_name: str, band: str | None, month: int,
                    range_m: float | None) -> np.ndarray:
    """The map's value at every position (NaN where the table is not built), km or dB."""
    m = atlas.month_index(month)
    out = np.full(atlas.lat_deg.size, np.nan)
    for o in range(atlas.lat_deg.size):
        if not atlas.done[m, o]:
            continue
        tables = atlas.sel(month=month, origin=o)
        if what is AtlasWhat.DETECTION:
            dm = detection_map(tables, cls_name, atlas.bearing_deg)
            ranges = dm.range_m if band is None else dm.band_range_m[tables.band_index(band)]
            out[o] = np.nanmedian(np.where(np.isfinite(ranges), ranges, 0.0)) / 1000.0
        else:
            ib = tables.band_index(band) if band is not None else 0
            k = tables.k_at(tables.class_index(cls_name), np.full(atlas.bearing_deg.size, range_m),
                            bearing_deg=atlas.bearing_deg)[ib]
            out[o] = np.nanmedian(k) if np.isfinite(k).any() else np.nan
    return out


def coverage_figure(atlas: AtlasTables, *, what: AtlasWhat | str = AtlasWhat.DETECTION, cls_name: str | None = None,
                    band: str | None = None, month: int | None = None, range_m: float | None = None):
    """The coverage map (a ``Figure``). Raises InputError for a class, band or month not in the atlas."""
    what = AtlasWhat(what)
    cls_name = cls_name if cls_name is not None else atlas.class_names[0]
    if cls_name not in atlas.class_names:
        raise InputError(f"{atlas.path}: class {cls_name!r} is not in the atlas ({', '.join(atlas.class_names)})")
    if band is not None and band not in atlas.band_names:
        raise InputError(f"{atlas.path}: band {band!r} is not in the atlas ({', '.join(atlas.band_names)})")
    month = int(atlas.months[0]) if month is None else month
    atlas.month_index(month)
    if what is AtlasWhat.K:
        range_m = float(atlas.range_m[atlas.range_m.size // 2]) if range_m is None else range_m
        if not atlas.range_m[0] <= range_m <= atlas.range_m[-1]:
            raise InputError(f"{atlas.path}: range {range_m / 1000:g} km is outside the tables' "
                             f"{atlas.range_m[0] / 1000:g}-{atlas.range_m[-1] / 1000:g} km")
    values = coverage_values(atlas, what=what, cls_name=cls_name, band=band, month=month, range_m=range_m)
    fig = new_figure(figsize=(7.5, 6.0), layout="constrained")
    ax = fig.add_subplot()
    # the water depth where the atlas's radials sampled it, from the tables of the first month
    lats, lons, depths = [], [], []
    for o in range(atlas.lat_deg.size):
        if not atlas.done[0, o]:
            continue
        bottom = atlas.slab(0, o)[2]
        for j, bearing in enumerate(atlas.bearing_deg):
            la, lo = geodesic_points(atlas.lat_deg[o], atlas.lon_deg[o], bearing, atlas.range_m)
            lats.append(la)
            lons.append(lo)
            depths.append(bottom[j])
    if lats:
        la, lo, d = np.concatenate(lats), np.concatenate(lons), np.concatenate(depths)
        wet = np.isfinite(d)
        if wet.sum() >= 3:
            cf = ax.tricontourf(lo[wet], la[wet], d[wet], levels=12, cmap="Blues")
            fig.colorbar(cf, ax=ax, label="water depth, m", shrink=0.8)
    label = (f"median detection range of {cls_name} ({band or 'any band'}), km" if what is AtlasWhat.DETECTION
             else f"median K of {cls_name} in {band or atlas.band_names[0]} at {range_m / 1000:g} km, dB")
    sc = ax.scatter(atlas.lon_deg, atlas.lat_deg, c=values, s=120, cmap="viridis", edgecolors="k", zorder=3)
    fig.colorbar(sc, ax=ax, label=label, shrink=0.8)
    if atlas.left_out:
        ax.scatter([p["lon_deg"] for p in atlas.left_out], [p["lat_deg"] for p in atlas.left_out], marker="x",
                   c="0.3", label="left out (land, shallow)", zorder=3)
        ax.legend(loc="lower left", fontsize=8)
    ax.set_xlabel("longitude, deg E")
    ax.set_ylabel("latitude, deg N")
    ax.set_aspect(1.0 / np.cos(np.radians(float(np.mean(atlas.lat_deg)))))
    ax.set_title(f"atlas {atlas.area.name}, month {month}: {atlas.lat_deg.size} positions")
    return fig, values
