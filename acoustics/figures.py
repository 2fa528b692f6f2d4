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


def save_figure(fig: Figure, path: str | os.PathLike, *, dpi: int = 110) -> Path:
    """Write ``fig`` as PNG to ``path`` through a temporary file renamed on success.

    Returns the path written. A failed save leaves ``path`` as it was.
    """
    if not isinstance(fig.canvas, FigureCanvasAgg):
        FigureCanvasAgg(fig)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=dpi)
    return Path(path)
