"""Figures: matplotlib's object API on the Agg canvas, saved through a temporary file.

No pyplot and no ``matplotlib.use``: importing a plotting module never changes the process's
backend, and a figure is never left open in a global registry.
"""

from __future__ import annotations

import os
from pathlib import Path

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from envdata.files import atomic_path


def new_figure(**kwargs) -> Figure:
    """A ``matplotlib.figure.Figure`` attached to an Agg canvas (``figsize``, ``layout``, ...)."""
    fig = Figure(**kwargs)
    FigureCanvasAgg(fig)
    return fig


def save_figure(fig: Figure, path: str | os.PathLike, *, dpi: int = 110,
                atomic: bool = True) -> Path:
    """Write ``fig`` as PNG to ``path``; returns the path written.

    With ``atomic`` (the default) through a temporary file renamed on success, so a failed save
    leaves ``path`` as it was; without, straight to ``path`` (for a caller that renames several
    files together).
    """
    if not isinstance(fig.canvas, FigureCanvasAgg):
        FigureCanvasAgg(fig)
    if not atomic:
        fig.savefig(path, format="png", dpi=dpi)
        return Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=dpi)
    return Path(path)
