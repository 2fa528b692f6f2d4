"""The plots of a bearing-dependent grid as files: the map, the bottom and a section, all or none.

``tmakit grids plot FILE --out PNG`` on a grid with bearings writes ``PNG`` (the map,
``acoustics.mapplot``), ``STEM-bottom.png`` (``acoustics.bottomplot``) and, given a bearing,
``STEM-section.png`` (``acoustics.sectionplot``) beside it, STEM being PNG's name without its
suffix. Separate files rather than panels of one figure: each stays readable at any number of
classes, and the map is the one a report takes. They are written through temporary files and
renamed together (``envdata.files.atomic_paths``).
"""

from __future__ import annotations

from pathlib import Path

import xarray as xr
from matplotlib.figure import Figure

from acoustics.bottomplot import bottom_figure
from acoustics.figures import save_figure
from acoustics.mapplot import map_figure
from acoustics.radialstyle import DPI, What, check_plot_options, grid_source
from acoustics.sectionplot import section_figure
from envdata.bathymetry import ElevationGrid
from envdata.errors import InputError
from envdata.files import atomic_paths


def bearing_plot_paths(out: str | Path, *, section: bool = False) -> dict[str, Path]:
    """The files a bearing-dependent plot writes: {"map": out, "bottom": STEM-bottom.png[,
    "section": STEM-section.png]}, beside ``out``."""
    out = Path(out)
    paths = {"map": out, "bottom": out.with_name(f"{out.stem}-bottom.png")}
    if section:
        paths["section"] = out.with_name(f"{out.stem}-section.png")
    return paths


def plot_bearing_grid(ds: xr.Dataset, out: str | Path, *, what: What | str = What.K,
                      cls_name: str | None = None, band: str | None = None,
                      bearing_deg: float | None = None, bathymetry: ElevationGrid | None = None,
                      bathymetry_note: str = "") -> dict[str, Path]:
    """Write the map, the bottom plot and (with ``bearing_deg``) the section, all or none.

    Parameters
    ----------
    ds : xr.Dataset
        A bearing-dependent grid (``acoustics.open_grid``).
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
        The bathymetry file's cells around the origin (``acoustics.gridbathymetry``): adds the
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
        An unknown class or band, a bearing outside [0, 360) deg, or a grid without bearings.
    """
    if "bearing" not in ds.dims:
        raise InputError(f"{grid_source(ds)}: the grid does not depend on bearing; plot it with "
                         f"acoustics.plot.plot_grid")
    check_plot_options(ds, cls_name=cls_name, band=band, bearing_deg=bearing_deg)
    paths = bearing_plot_paths(out, section=bearing_deg is not None)
    figures = {"map": map_figure(ds, what=what, classes=None if cls_name is None else [cls_name], band=band,
                                 bathymetry=bathymetry, bathymetry_note=bathymetry_note),
               "bottom": bottom_figure(ds)}
    if bearing_deg is not None:
        figures["section"] = section_figure(ds, bearing_deg=bearing_deg, cls_name=cls_name, band=band)
    write_figures({paths[key]: fig for key, fig in figures.items()})
    return paths


def write_figures(figures: dict[Path, Figure], dpi: int = DPI) -> None:
    """Save several figures as PNG: all of them, or on any failure none (``atomic_paths``)."""
    targets = list(figures)
    with atomic_paths(targets) as temps:
        for tmp, target in zip(temps, targets):
            save_figure(figures[target], tmp, dpi=dpi, atomic=False)  # atomic_paths renames them
