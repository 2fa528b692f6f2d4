"""The map around the origin of a bearing-dependent grid.

README "What it does" (``grids plot``): for a bearing-dependent grid, the map around the origin, K(r) or the
detection range per band and class. One polar panel per class (north up, bearings clockwise,
range outward in km) with

- K(r) in one band as colour, between radials linear in bearing as the trackers take it; blank
  where the grid has no K (the class deeper than the water there, or beyond land); or
- the detection range of each band and of any band, the target at its class's mean level
  (``acoustics.detection``), as lines and a filled area;

and on every panel the depth contours of the grid's own ``bottom_depth_m``, land (where the
grid has no bottom) shaded, the radials dotted and the origin starred. With the bathymetry
file at hand (``acoustics.plots.bathymetry``) one more panel on latitude and longitude: the file's
relief, coast and depth contours, the radials, the grid's last range and the detection outlines.
"""

from __future__ import annotations

import math

import numpy as np
from matplotlib.figure import Figure

from acoustics.grid.detectionmap import detection_map
from acoustics.grid.radialtables import RadialTables
from acoustics.plots.figures import new_figure
from acoustics.plots.style import (
    DEG,
    LAND_COLOR,
    ORIGIN_STYLE,
    band_label,
    check_plot_options,
    class_label,
    contour_levels,
    label_depth,
    origin_label,
)
from acoustics.plots.what import What
from envdata.bathymetry import ElevationGrid
from envdata.radials import geodesic_points

#: Bearing resolution of the map between radials, deg.
MAP_STEP_DEG = 1.0
#: Where any band is detected (apart from the bands' own colours and from land).
ANY_BAND_COLOR = "#a6cee3"


def map_bearings(grid_bearings_deg) -> np.ndarray:
    """Bearings the map evaluates, deg: every `MAP_STEP_DEG` and every radial, increasing."""
    fine = np.arange(0.0, 360.0, MAP_STEP_DEG)
    return np.unique(np.concatenate([fine, np.asarray(grid_bearings_deg, dtype=float)]))


def map_figure(tables: RadialTables, *, what: What | str = What.K, classes: list[str] | None = None,
               band: str | None = None, bathymetry: ElevationGrid | None = None,
               bathymetry_note: str = "") -> Figure:
    """The map around the origin (module docstring).

    Parameters
    ----------
    tables : RadialTables
        A bearing-dependent grid.
    what : {"k", "detection"}
    classes : list of str, optional
        Classes to draw, one panel each (default: all).
    band : str, optional
        Band of the K map (default: the first); the detection map draws every band.
    bathymetry : ElevationGrid, optional
        The bathymetry file's cells around the origin, for the latitude-longitude panel.
    bathymetry_note : str
        Said under that panel's title (how the file was found).

    Notes
    -----
    Artists carry ``gid``s: ``k:CLASS`` (the K mesh), ``detection:CLASS`` and
    ``detection:CLASS:BAND`` (closed lines: bearing in radians, range in km; the last point
    repeats the first), ``origin``.
    """
    what = What(what)
    classes = list(tables.class_names) if classes is None else list(classes)
    band = tables.band_names[0] if band is None else band
    check_plot_options(tables, band=band)
    for c in classes:
        check_plot_options(tables, cls_name=c)
    bearings = map_bearings(tables.bearing_deg)
    r_km = tables.range_m / 1000.0
    bottom = tables.bottom_at(bearings)
    n_panels = len(classes) + (bathymetry is not None)
    ncols = n_panels if n_panels <= 3 else math.ceil(n_panels / 2)
    nrows = math.ceil(n_panels / ncols)
    fig = new_figure(figsize=(4.7 * ncols + 0.4, 5.2 * nrows + 1.2), layout="constrained")
    axes = [fig.add_subplot(nrows, ncols, i + 1, projection="polar") for i in range(len(classes))]
    where = (f"area {tables.area_name}, origin {origin_label(tables)}, observer at "
             f"{tables.observer_depth_m:g} m\nbearing clockwise from true north, range in km; "
             f"between the radials (dotted) linear in bearing; contours: the grid's bottom_depth_m")
    outlines: dict[str, np.ndarray] = {}
    if what is What.K:
        _k_panels(tables, fig, axes, classes, band, bearings, bottom, r_km)
        fig.suptitle(f"Transfer characteristic K(r) in band {band_label(tables, band)} per class\nblank: no K "
                     f"(the class deeper than the water there); tan: land\n{where}", fontsize=9.5)
    else:
        terms = _detection_panels(tables, fig, axes, classes, bearings, bottom, r_km, outlines)
        fig.suptitle(f"Detection range per band, the target at its class's mean level\ndetected where "
                     f"Q = q\u221a(\u0394f T) \u2265 {terms.threshold:g}; tan: land\n{tables.sonar_label()}\n{where}",
                     fontsize=9.5)
    if bathymetry is not None:
        ax = fig.add_subplot(nrows, ncols, len(classes) + 1)
        latlon_panel(tables, ax, bathymetry, outlines, bearings, bathymetry_note)
    return fig


def _k_panels(tables, fig, axes, classes, band, bearings, bottom, r_km) -> None:
    ib = tables.band_index(band)
    k_all = tables.k_grid_db[:, ib]
    finite = k_all[np.isfinite(k_all)]
    vmin, vmax = np.percentile(finite, [2, 98]) if finite.size else (-120.0, -40.0)
    mesh = None
    for ax, c in zip(axes, classes):
        k = tables.k_db(None, bearings)[tables.class_index(c), ib]                 # (B, R)
        mesh = ax.pcolormesh(np.radians(bearings), r_km, k.T, shading="nearest", cmap="viridis",
                             vmin=vmin, vmax=vmax, zorder=0, rasterized=True)
        mesh.set_gid(f"k:{c}")
        polar_setting(tables, ax, bearings, bottom, r_km)
        ax.set_title(f"class {class_label(tables, c)}", fontsize=9.5)
    fig.colorbar(mesh, ax=axes, orientation="horizontal", shrink=0.6, aspect=45,
                 label=f"K(r), dB, in band {band_label(tables, band)} (band level W = P0 + K(r) + H)")


def _detection_panels(tables, fig, axes, classes, bearings, bottom, r_km, outlines):
    import matplotlib

    colors = matplotlib.colormaps["tab10"]
    band_names = tables.band_names
    theta = np.radians(np.append(bearings, bearings[0] + 360.0))  # closed outlines
    terms = None
    for ax, c in zip(axes, classes):
        dm = detection_map(tables, c, bearings)
        terms = dm.terms
        any_km = np.append(dm.range_m, dm.range_m[0]) / 1000.0
        ax.fill(theta, np.nan_to_num(any_km, nan=0.0), color=ANY_BAND_COLOR, alpha=0.45, zorder=0,
                label="any band")
        line, = ax.plot(theta, any_km, color="k", lw=3.0, alpha=0.25, zorder=4)
        line.set_gid(f"detection:{c}")
        for i, b in enumerate(band_names):
            km = np.append(dm.band_range_m[i], dm.band_range_m[i][0]) / 1000.0
            line, = ax.plot(theta, km, color=colors(i), lw=max(2.0 - 0.5 * i, 0.8), zorder=5,
                            ls=("-", "--", ":", "-.")[i % 4], label=band_label(tables, b))
            line.set_gid(f"detection:{c}:{b}")
        outlines[c] = dm.range_m
        polar_setting(tables, ax, bearings, bottom, r_km)
        ax.set_title(f"class {class_label(tables, c)}, {dm.terms.level_label}\n{_span(dm.range_m)}", fontsize=9.5)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=len(labels), fontsize=8,
               title="detected out to (the outer circle is the grid's last range)", title_fontsize=8)
    return terms


def _span(range_m: np.ndarray) -> str:
    """How far any band is detected, over the bearings, for a panel's title."""
    found = range_m[np.isfinite(range_m)] / 1000.0
    if not found.size:
        return "detected nowhere"
    if found.min() == found.max():
        return f"any band detected out to {found.max():g} km"
    return f"any band detected out to {found.min():g}-{found.max():g} km"


def polar_setting(tables: RadialTables, ax, bearings: np.ndarray, bottom: np.ndarray, r_km: np.ndarray) -> None:
    """Land, the grid's depth contours, the radials, the origin and the axes of a polar panel."""
    from matplotlib.colors import ListedColormap

    theta = np.radians(bearings)
    land = np.where(np.isfinite(bottom), np.nan, 1.0)
    ax.pcolormesh(theta, r_km, land.T, shading="nearest", cmap=ListedColormap([LAND_COLOR]), vmin=0,
                  vmax=1, zorder=1, rasterized=True)
    levels = contour_levels(bottom)
    if levels:
        cs = ax.contour(theta, r_km, bottom.T, levels=levels, colors="k", linewidths=0.6, alpha=0.6,
                        zorder=3)
        ax.clabel(cs, fmt=label_depth, fontsize=6, inline=True)
    for b in tables.bearing_deg:
        ax.plot([math.radians(float(b))] * 2, [0.0, r_km[-1]], color="0.35", lw=0.5, ls=":", zorder=2)
    origin, = ax.plot([0.0], [0.0], ms=11, zorder=6, **ORIGIN_STYLE)
    origin.set_gid("origin")
    ax.set_theta_zero_location("N")
    ax.set_theta_direction(-1)
    ax.set_rlim(0.0, r_km[-1])
    ax.set_rlabel_position(112.5)
    ax.yaxis.set_major_formatter(lambda v, pos: f"{v:g} km")
    ax.tick_params(labelsize=7)
    ax.set_thetagrids(np.arange(0, 360, 45), [f"{b}{DEG}" for b in range(0, 360, 45)], fontsize=8)
    ax.grid(alpha=0.35)


def latlon_panel(tables: RadialTables, ax, bathy: ElevationGrid, outlines: dict[str, np.ndarray],
                 bearings: np.ndarray, note: str, said: str = "detected out to", gaps: bool = False) -> None:
    """The bathymetry file's relief and contours on lat/lon axes, with the radials and outlines
    (``said`` after each class's name in the legend; with ``gaps`` an outline's NaN is a gap, else
    no range: the origin)."""
    import matplotlib

    lat0, lon0 = tables.origin_lat_deg, tables.origin_lon_deg
    mesh = draw_relief(ax, bathy)
    rng = tables.range_m
    for b, row in zip(tables.bearing_deg, tables.bottom_depth_m):
        wet = np.isfinite(row)
        end = float(rng[wet][-1]) if wet.any() else 0.0
        lat, lon = geodesic_points(lat0, lon0, float(b), np.linspace(0.0, end, 24))
        ax.plot(_near(lon, lon0), lat, color="0.25", lw=0.6, ls=":")
    colors = matplotlib.colormaps["Set1"]
    for i, (c, rr) in enumerate(outlines.items()):
        lat, lon = _ring(lat0, lon0, bearings, np.nan_to_num(rr, nan=0.0))
        if gaps:
            missing = np.isnan(np.append(rr, rr[0]))
            lat, lon = np.where(missing, np.nan, lat), np.where(missing, np.nan, lon)
        ax.plot(_near(lon, lon0), lat, color=colors(i), lw=1.5 if i == 0 else 1.2,
                ls=("-", "--", "-.", ":")[i % 4], label=f"{c}: {said}")
    r_max = float(rng[-1])
    ring_b = np.arange(0.0, 360.0, 5.0)
    lat, lon = _ring(lat0, lon0, ring_b, np.full(ring_b.shape, r_max))
    ax.plot(_near(lon, lon0), lat, color="0.2", lw=0.8, ls="--", label=f"grid's last range, {r_max / 1000:g} km")
    ax.plot([lon0], [lat0], ms=12, label="origin (observer)", **ORIGIN_STYLE)
    ax.set_aspect(1.0 / math.cos(math.radians(lat0)))
    ax.set_xlabel(f"longitude, {DEG}E")
    ax.set_ylabel(f"latitude, {DEG}N")
    ax.tick_params(labelsize=7)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2)
    ax.figure.colorbar(mesh, ax=ax, shrink=0.75, label="water depth in the file, m")
    ax.set_title(f"bathymetry file {bathy.path.name}: depth contours, land (tan)"
                 + (f"\n{note}" if note else ""), fontsize=8.5)


def draw_relief(ax, bathy: ElevationGrid):
    """A bathymetry file's water depth (blues), land (tan), depth contours and the coast on
    latitude-longitude axes; returns the depth mesh (for a colour bar)."""
    from matplotlib.colors import ListedColormap

    depth = -bathy.elevation_m
    water = np.where(depth > 0, depth, np.nan)
    deepest = float(np.nanmax(water)) if np.isfinite(water).any() else 1.0
    mesh = ax.pcolormesh(bathy.lon_deg, bathy.lat_deg, water, shading="nearest", cmap="Blues",
                         vmin=0.0, vmax=max(deepest, 1.0), rasterized=True)
    ax.pcolormesh(bathy.lon_deg, bathy.lat_deg, np.where(depth <= 0, 1.0, np.nan), shading="nearest",
                  cmap=ListedColormap([LAND_COLOR]), vmin=0, vmax=1, rasterized=True)
    levels = contour_levels(depth)
    if levels:
        cs = ax.contour(bathy.lon_deg, bathy.lat_deg, depth, levels=levels, colors="k", linewidths=0.6,
                        alpha=0.7)
        ax.clabel(cs, fmt=label_depth, fontsize=6)
    if np.nanmin(depth) < 0.0 < np.nanmax(depth):
        ax.contour(bathy.lon_deg, bathy.lat_deg, depth, levels=[0.0], colors="saddlebrown", linewidths=1.0)
    return mesh


def _ring(lat0: float, lon0: float, bearings: np.ndarray, range_m: np.ndarray):
    """Closed line through the points at ``range_m`` along each bearing from the origin, deg."""
    pts = [geodesic_points(lat0, lon0, float(b), [float(r)]) for b, r in zip(bearings, range_m)]
    lat = np.array([p[0][0] for p in pts])
    lon = np.array([p[1][0] for p in pts])
    return np.append(lat, lat[0]), np.append(lon, lon[0])


def _near(lon: np.ndarray, lon0: float) -> np.ndarray:
    """Longitudes continuous around the origin's."""
    return lon0 + np.mod(np.asarray(lon, dtype=float) - lon0 + 180.0, 360.0) - 180.0
