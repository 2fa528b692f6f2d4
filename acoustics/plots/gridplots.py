"""A grid's figures as files, whatever its geometry: what ``tmakit grids plot`` writes.

A grid without bearings gets one PNG (``acoustics.plots.flatplot``: TL fields and K(r) curves);
a bearing-dependent grid the map around the origin, the bottom along the radials and, given a
bearing, a TL section (``acoustics.plots.radialplots``), with the bathymetry file behind the grid
on the map when it is at hand (``acoustics.plots.bathymetry``). Asked for K against target
depth (`What.DEPTH`), either gets that one PNG (``acoustics.plots.depthplot``). Asked for the
probability of detection (`What.PD`), a bearing-dependent grid's map comes with its CF netCDF on
latitude and longitude beside it (``acoustics.grid.pdfile``); a grid without bearings gets P_D
against range, one PNG. The choice follows the grid's
type: callers pass the typed face and a `PlotRequest`, and never ask which geometry it is.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from pathlib import Path

from acoustics.grid.detectionsigma import SigmaOverride
from acoustics.grid.face import Tables
from acoustics.grid.flattables import FlatTables
from acoustics.grid.pdmap import check_band
from acoustics.grid.radialtables import RadialTables
from acoustics.plots.bathymetry import BathymetryChoice, find_bathymetry, load_around_origin
from acoustics.plots.style import check_plot_options
from acoustics.plots.what import What
from envdata.errors import InputError


@dataclass(frozen=True, slots=True, kw_only=True)
class PlotRequest:
    """What to draw.

    Attributes
    ----------
    cls_name : str, optional
        The class of the TL field or section, and the only class on a map (default: the first;
        every class on a map).
    band : str, optional
        The band of a K map and of a section (bearing-dependent grids; default: the first).
    what : What, optional
        A map's K(r) in ``band`` or its detection ranges (bearing-dependent grids; default K), or
        K against target depth and range in ``band`` (any grid with TL from the observer).
    bearing_deg : float, optional
        A section, or K against target depth, on the radial nearest to this bearing, deg
        (bearing-dependent grids).
    bathymetry : Path, optional
        A bathymetry file for the map's latitude-longitude panel (default: the file the grid
        records, when it is found by its name and sha256).
    grid_path : Path, optional
        Where the grid file is (the recorded bathymetry file is looked for beside it).
    sigma : SigmaOverride, optional
        The user's sigma for P_D (`What.PD` only).
    """

    cls_name: str | None = None
    band: str | None = None
    what: What | None = None
    bearing_deg: float | None = None
    bathymetry: Path | None = None
    grid_path: Path | None = None
    sigma: SigmaOverride | None = None


@dataclass(frozen=True, slots=True, kw_only=True)
class GridPlots:
    """What was written: {role: path}, the bathymetry file drawn (None when none was), and for
    `What.PD` the P_D maps of the summary (class -> ``PDMap`` on the radials) and the row drawn."""

    files: dict[str, Path]
    what: What | None = None
    bathymetry: BathymetryChoice | None = None
    notes: tuple[str, ...] = field(default_factory=tuple)
    pd_maps: dict = field(default_factory=dict)
    pd_row: str | None = None


@functools.singledispatch
def plot_paths(tables: Tables, out: str | Path, request: PlotRequest) -> dict[str, Path]:
    """The files ``plot_grid`` writes for a request, {role: path}: to check before drawing."""
    raise TypeError(f"no figures for {type(tables).__name__}")


@plot_paths.register
def _(tables: FlatTables, out: str | Path, request: PlotRequest) -> dict[str, Path]:
    return {{What.DEPTH: "depth", What.PD: "pd"}.get(request.what, "plot"): Path(out)}


@plot_paths.register
def _(tables: RadialTables, out: str | Path, request: PlotRequest) -> dict[str, Path]:
    from acoustics.plots.radialplots import bearing_plot_paths

    if request.what == What.DEPTH:
        return {"depth": Path(out)}
    return bearing_plot_paths(out, section=request.bearing_deg is not None, netcdf=request.what == What.PD)


@functools.singledispatch
def plot_grid(tables: Tables, out: str | Path, request: PlotRequest = PlotRequest()) -> GridPlots:
    """Write a grid's figures (module docstring), all or none.

    Raises
    ------
    InputError
        A class or band the grid does not have, a bearing outside [0, 360) deg, or an option
        the grid's geometry has no figure for.
    """
    raise TypeError(f"no figures for {type(tables).__name__}")


#: Options that only a bearing-dependent grid's figures take, and how a message names them.
_BEARING_ONLY = {"band": "a map's band", "what": "a map (K or detection ranges)",
                 "bearing_deg": "a section's bearing", "bathymetry": "a bathymetry file"}


def _check_sigma(tables: Tables, request: PlotRequest) -> None:
    if request.sigma is not None and request.what != What.PD:
        raise InputError(f"{tables.source}: --sigma-db is for the probability of detection (--what pd)")


def _depth_plot(tables: Tables, out: str | Path, request: PlotRequest) -> GridPlots:
    """K against target depth and range (`What.DEPTH`), on any grid's face."""
    from acoustics.plots.depthplot import plot_target_depth

    if request.bathymetry is not None:
        raise InputError(f"{tables.source}: a bathymetry file is drawn on the map; the figure of K "
                         f"against target depth has no map")
    path = plot_target_depth(tables, out, cls_name=request.cls_name, band=request.band,
                             bearing_deg=request.bearing_deg)
    return GridPlots(files={"depth": path}, what=What.DEPTH)


@plot_grid.register
def _(tables: FlatTables, out: str | Path, request: PlotRequest = PlotRequest()) -> GridPlots:
    from acoustics.plots.flatplot import plot_flat_grid

    _check_sigma(tables, request)
    if request.what == What.PD:
        return _pd_curves(tables, out, request)
    if request.what == What.DEPTH:
        if request.bearing_deg is not None:
            raise InputError(f"{tables.source}: a bearing is for a bearing-dependent grid; this grid "
                             f"has no bearings (its area has no [origin]), its K against target "
                             f"depth is the same along every bearing")
        return _depth_plot(tables, out, request)
    for name, said in _BEARING_ONLY.items():
        if getattr(request, name) is not None:
            raise InputError(f"{tables.source}: {said} is for a bearing-dependent grid; this grid "
                             f"has no bearings (its area has no [origin]), its TL is the same along "
                             f"every bearing")
    check_plot_options(tables, cls_name=request.cls_name)
    return GridPlots(files={"plot": plot_flat_grid(tables, out, cls_name=request.cls_name)})


@plot_grid.register
def _(tables: RadialTables, out: str | Path, request: PlotRequest = PlotRequest()) -> GridPlots:
    from acoustics.plots.radialplots import plot_bearing_grid

    _check_sigma(tables, request)
    if request.what == What.DEPTH:
        return _depth_plot(tables, out, request)
    if request.what == What.PD:
        check_band(tables, request.band)
    check_plot_options(tables, cls_name=request.cls_name, band=None if request.what == What.PD else request.band,
                       bearing_deg=request.bearing_deg)
    choice = find_bathymetry(tables, given=request.bathymetry, grid_path=request.grid_path)
    bathymetry, note = None, ""
    if choice is not None:
        bathymetry = load_around_origin(choice, tables.origin_lat_deg, tables.origin_lon_deg,
                                        float(tables.range_m[-1]))
        note = (f"{choice.how}; sha256 as the grid records" if choice.matches
                else "given; not the file the grid was built from (sha256 differs)")
    what = What(request.what or What.K)
    drawn = plot_bearing_grid(tables, out, what=what, cls_name=request.cls_name, band=request.band,
                              bearing_deg=request.bearing_deg, bathymetry=bathymetry,
                              bathymetry_note=note, sigma=request.sigma)
    return GridPlots(files=drawn.files, what=what, bathymetry=choice, notes=(note,) if note else (),
                     pd_maps=drawn.pd_maps, pd_row=drawn.pd_row)


def _pd_curves(tables: Tables, out: str | Path, request: PlotRequest) -> GridPlots:
    """P_D against range (`What.PD` on a grid without bearings): one PNG."""
    from acoustics.plots.figures import save_figure
    from acoustics.plots.pdplot import pd_curves_figure

    for name in ("bearing_deg", "bathymetry"):
        if getattr(request, name) is not None:
            raise InputError(f"{tables.source}: {_BEARING_ONLY[name]} is for a bearing-dependent grid; this grid "
                             f"has no bearings (its area has no [origin]), its P_D is the same along every bearing")
    check_plot_options(tables, cls_name=request.cls_name)
    row = check_band(tables, request.band)
    fig, maps = pd_curves_figure(tables, classes=None if request.cls_name is None else [request.cls_name],
                                 override=request.sigma)
    path = save_figure(fig, out)
    return GridPlots(files={"pd": path}, what=What.PD, pd_maps=maps, pd_row=row)
