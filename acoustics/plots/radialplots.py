"""The plots of a bearing-dependent grid as files: the map, the bottom and a section, all or none.

``tmakit grids plot FILE --out PNG`` on a grid with bearings writes ``PNG`` (the map,
``acoustics.plots.mapplot``, or with ``--what pd`` ``acoustics.plots.pdplot``, then with
``STEM.nc``, the same P_D on latitude and longitude for a GIS, ``acoustics.grid.pdfile``),
``STEM-bottom.png`` (``acoustics.plots.bottomplot``) and, given a bearing, ``STEM-section.png``
(``acoustics.plots.sectionplot``) beside it, STEM being PNG's name without its suffix. Separate
files rather than panels of one figure: each stays readable at any number of classes, and the
map is the one a report takes. They are written through temporary files and
renamed together (``envdata.files.atomic_paths``).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from matplotlib.figure import Figure

from acoustics.grid.detectionsigma import SigmaOverride
from acoustics.grid.pdfile import grid_pd_dataset, write_pd_file
from acoustics.grid.pdmap import ANY_BAND, check_band
from acoustics.grid.radialtables import RadialTables
from acoustics.plots.bottomplot import bottom_figure
from acoustics.plots.figures import save_figure
from acoustics.plots.mapplot import map_figure
from acoustics.plots.pdplot import pd_map_figure
from acoustics.plots.sectionplot import section_figure
from acoustics.plots.style import DPI, check_plot_options
from acoustics.plots.what import What
from envdata.bathymetry import ElevationGrid
from envdata.errors import InputError
from envdata.files import atomic_paths


def bearing_plot_paths(out: str | Path, *, section: bool = False, netcdf: bool = False) -> dict[str, Path]:
    """The files a bearing-dependent plot writes: {"map": out[, "netcdf": STEM.nc], "bottom":
    STEM-bottom.png[, "section": STEM-section.png]}, beside ``out``.

    Raises
    ------
    InputError
        With the netCDF, an ``out`` named ``.nc`` (the netCDF would replace the PNG).
    """
    out = Path(out)
    paths = {"map": out}
    if netcdf:
        paths["netcdf"] = out.with_name(f"{out.stem}.nc")
        if paths["netcdf"] == out:
            raise InputError(f"{out}: the map's PNG needs a name of its own (say {out.stem}.png): its netCDF "
                             f"goes beside it as {out.name}")
    paths["bottom"] = out.with_name(f"{out.stem}-bottom.png")
    if section:
        paths["section"] = out.with_name(f"{out.stem}-section.png")
    return paths


@dataclass(frozen=True, slots=True, kw_only=True)
class BearingPlots:
    """What `plot_bearing_grid` wrote ({role: path}) and, for P_D, the P_D maps of the radials by
    class and the band (or ``"any"``) drawn."""

    files: dict[str, Path]
    pd_maps: dict = field(default_factory=dict)
    pd_row: str | None = None


def plot_bearing_grid(tables: RadialTables, out: str | Path, *, what: What | str = What.K,
                      cls_name: str | None = None, band: str | None = None,
                      bearing_deg: float | None = None, bathymetry: ElevationGrid | None = None,
                      bathymetry_note: str = "", sigma: SigmaOverride | None = None) -> BearingPlots:
    """Write the map (with P_D its netCDF), the bottom plot and (with ``bearing_deg``) the section,
    all or none.

    Parameters
    ----------
    tables : RadialTables
        A bearing-dependent grid (``acoustics.open_tables``).
    out : path
        The map's PNG; the others go beside it (``bearing_plot_paths``).
    what : {"k", "detection", "pd"}
        The map's K(r) in ``band``, the detection range per band, or P_D in ``band`` (a band or
        "any", the default).
    cls_name : str, optional
        The only class on the map, and the section's class (default: every class on the map,
        the first in the section).
    band : str, optional
        The band of the K or P_D map and of the section (default: the first band; any band for P_D).
    bearing_deg : float, optional
        The section's bearing, deg in [0, 360): the radial nearest to it is drawn; no section
        without it.
    bathymetry : ElevationGrid, optional
        The bathymetry file's cells around the origin (``acoustics.plots.bathymetry``): adds the
        latitude-longitude panel to the map.
    bathymetry_note : str
        Said on that panel (which file, how it was found).
    sigma : SigmaOverride, optional
        The user's sigma for P_D.

    Returns
    -------
    BearingPlots
        {"map"[, "netcdf"], "bottom"[, "section"]: the path written}, and the P_D maps.

    Raises
    ------
    InputError
        An unknown class or band, or a bearing outside [0, 360) deg.
    """
    what = What(what)
    pd_row = check_band(tables, band) if what is What.PD else None
    check_plot_options(tables, cls_name=cls_name, band=None if what is What.PD else band, bearing_deg=bearing_deg)
    paths = bearing_plot_paths(out, section=bearing_deg is not None, netcdf=what is What.PD)
    classes = None if cls_name is None else [cls_name]
    datasets, pd_maps = {}, {}
    if what is What.PD:
        fig, pd_maps = pd_map_figure(tables, band=pd_row, classes=classes, override=sigma, bathymetry=bathymetry,
                                     bathymetry_note=bathymetry_note)
        datasets[paths["netcdf"]] = grid_pd_dataset(tables, pd_row, classes=classes, override=sigma)
    else:
        fig = map_figure(tables, what=what, classes=classes, band=band, bathymetry=bathymetry,
                         bathymetry_note=bathymetry_note)
    figures = {"map": fig, "bottom": bottom_figure(tables)}
    if bearing_deg is not None:
        section_band = None if pd_row == ANY_BAND else band
        figures["section"] = section_figure(tables, bearing_deg=bearing_deg, cls_name=cls_name, band=section_band)
    write_figures({paths[key]: fig for key, fig in figures.items()}, datasets=datasets)
    return BearingPlots(files=paths, pd_maps=pd_maps, pd_row=pd_row)


def write_figures(figures: dict[Path, Figure], dpi: int = DPI, *, datasets: dict | None = None) -> None:
    """Save several figures as PNG (and P_D map datasets as netCDF): all of them, or on any failure
    none (``atomic_paths``)."""
    datasets = datasets or {}
    targets = [*figures, *datasets]
    with atomic_paths(targets) as temps:
        for tmp, target in zip(temps, targets):
            if target in figures:
                save_figure(figures[target], tmp, dpi=dpi, atomic=False)  # atomic_paths renames them
            else:
                write_pd_file(datasets[target], tmp, atomic=False)


def plot_map_set(tables: RadialTables, pngs: dict[str, Path], *, grid_path: str | Path | None = None
                 ) -> None:
    """The K map, the detection map, the P_D map (any band) with its netCDF, and the bottom of a
    grid, written all or none.

    ``pngs`` maps "k", "detection", "pd", "pd-netcdf" and "bottom" to the files ("pd" and
    "pd-netcdf" optional); the bathymetry file the grid records is drawn on the maps when it is
    found (``acoustics.plots.bathymetry``).
    """
    from acoustics.plots.bathymetry import find_bathymetry, load_around_origin

    choice = find_bathymetry(tables, grid_path=grid_path)
    bathymetry = (load_around_origin(choice, tables.origin_lat_deg, tables.origin_lon_deg,
                                     float(tables.range_m[-1])) if choice is not None else None)
    note = f"{choice.how}; sha256 as the grid records" if choice is not None else ""
    figures = {pngs["k"]: map_figure(tables, what=What.K, bathymetry=bathymetry, bathymetry_note=note),
               pngs["detection"]: map_figure(tables, what=What.DETECTION, bathymetry=bathymetry,
                                             bathymetry_note=note),
               pngs["bottom"]: bottom_figure(tables)}
    datasets = {}
    if "pd" in pngs:
        figures[pngs["pd"]] = pd_map_figure(tables, band=ANY_BAND, bathymetry=bathymetry, bathymetry_note=note)[0]
        datasets[pngs["pd-netcdf"]] = grid_pd_dataset(tables, ANY_BAND)
    write_figures(figures, datasets=datasets)
