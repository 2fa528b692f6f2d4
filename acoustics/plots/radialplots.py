"""The plots of a bearing-dependent grid as files: the map, the bottom and a section, all or none.

``tmakit grids plot FILE --out PNG`` on a grid with bearings writes ``PNG`` (the map,
``acoustics.plots.mapplot``), ``STEM-bottom.png`` (``acoustics.plots.bottomplot``) and, given a bearing,
``STEM-section.png`` (``acoustics.plots.sectionplot``) beside it, STEM being PNG's name without its
suffix. Separate files rather than panels of one figure: each stays readable at any number of
classes, and the map is the one a report takes. They are written through temporary files and
renamed together (``envdata.files.atomic_paths``).
"""

from __future__ import annotations

from pathlib import Path

from matplotlib.figure import Figure

from acoustics.grid.radialtables import RadialTables
from acoustics.plots.bottomplot import bottom_figure
from acoustics.plots.figures import save_figure
from acoustics.plots.mapplot import map_figure
from acoustics.plots.sectionplot import section_figure
from acoustics.plots.style import DPI, check_plot_options
from acoustics.plots.what import What
from envdata.bathymetry import ElevationGrid
from envdata.files import atomic_paths


def bearing_plot_paths(out: str | Path, *, section: bool = False) -> dict[str, Path]:
    """The files a bearing-dependent plot writes: {"map": out, "bottom": STEM-bottom.png[,
    "section": STEM-section.png]}, beside ``out``."""
    out = Path(out)
    paths = {"map": out, "bottom": out.with_name(f"{out.stem}-bottom.png")}
    if section:
        paths["section"] = out.with_name(f"{out.stem}-section.png")
    return paths


def plot_bearing_grid(tables: RadialTables, out: str | Path, *, what: What | str = What.K,
                      cls_name: str | None = None, band: str | None = None,
                      bearing_deg: float | None = None, bathymetry: ElevationGrid | None = None,
                      bathymetry_note: str = "") -> dict[str, Path]:
    """Write the map, the bottom plot and (with ``bearing_deg``) the section, all or none.

    Parameters
    ----------
    tables : RadialTables
        A bearing-dependent grid (``acoustics.open_tables``).
    out : path
        The map's PNG; the others go beside it (``bearing_plot_paths``).
    what : {"k", "detection"}
        The map's K(r) in ``band``, or the detection range per band.
    cls_name : str, optional
        The only class on the map, and the section's class (default: every class on the map,
        the first in the section).
    band : str, optional
        The band of the K map and of the section (default: the first band).
    bearing_deg : float, optional
        The section's bearing, deg in [0, 360): the radial nearest to it is drawn; no section
        without it.
    bathymetry : ElevationGrid, optional
        The bathymetry file's cells around the origin (``acoustics.plots.bathymetry``): adds the
        latitude-longitude panel to the map.
    bathymetry_note : str
        Said on that panel (which file, how it was found).

    Returns
    -------
    dict
        {"map", "bottom"[, "section"]: the path written}.

    Raises
    ------
    InputError
        An unknown class or band, or a bearing outside [0, 360) deg.
    """
    check_plot_options(tables, cls_name=cls_name, band=band, bearing_deg=bearing_deg)
    paths = bearing_plot_paths(out, section=bearing_deg is not None)
    figures = {"map": map_figure(tables, what=what, classes=None if cls_name is None else [cls_name], band=band,
                                 bathymetry=bathymetry, bathymetry_note=bathymetry_note),
               "bottom": bottom_figure(tables)}
    if bearing_deg is not None:
        figures["section"] = section_figure(tables, bearing_deg=bearing_deg, cls_name=cls_name, band=band)
    write_figures({paths[key]: fig for key, fig in figures.items()})
    return paths


def write_figures(figures: dict[Path, Figure], dpi: int = DPI) -> None:
    """Save several figures as PNG: all of them, or on any failure none (``atomic_paths``)."""
    targets = list(figures)
    with atomic_paths(targets) as temps:
        for tmp, target in zip(temps, targets):
            save_figure(figures[target], tmp, dpi=dpi, atomic=False)  # atomic_paths renames them


def plot_map_set(tables: RadialTables, pngs: dict[str, Path], *, grid_path: str | Path | None = None
                 ) -> None:
    """The K map, the detection map and the bottom of a grid, written all or none.

    ``pngs`` maps "k", "detection" and "bottom" to the files; the bathymetry file the grid
    records is drawn on the maps when it is found (``acoustics.plots.bathymetry``).
    """
    from acoustics.plots.bathymetry import find_bathymetry, load_around_origin

    choice = find_bathymetry(tables, grid_path=grid_path)
    bathymetry = (load_around_origin(choice, tables.origin_lat_deg, tables.origin_lon_deg,
                                     float(tables.range_m[-1])) if choice is not None else None)
    note = f"{choice.how}; sha256 as the grid records" if choice is not None else ""
    write_figures({pngs["k"]: map_figure(tables, what=What.K, bathymetry=bathymetry, bathymetry_note=note),
                   pngs["detection"]: map_figure(tables, what=What.DETECTION, bathymetry=bathymetry,
                                                 bathymetry_note=note),
                   pngs["bottom"]: bottom_figure(tables)})
