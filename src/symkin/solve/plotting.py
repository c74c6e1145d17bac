"""Matplotlib figures on an explicit Agg canvas, loaded on demand for the PNG plots.

Plots are an extra (``pip install symkin[plot]``): the core never imports matplotlib.  The
figures are ``matplotlib.figure.Figure`` objects with their own ``FigureCanvasAgg``, never
pyplot's: pyplot's backend and its list of open figures stay as the user set them (a Jupyter
session keeps its inline backend, a desktop session its window backend), and nothing needs
closing.
"""

from __future__ import annotations

import io
from pathlib import Path
from typing import Any

from symkin.errors import SymkinError
from symkin.output_folder import replace_file

PNG_DPI = 110


def new_figure(**options: Any) -> Any:
    """A ``matplotlib.figure.Figure`` (``options`` as for its constructor, e.g. ``figsize``)
    drawn by its own Agg canvas, unknown to pyplot."""
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
    except ImportError as error:
        raise SymkinError(
            "plots need matplotlib: pip install 'symkin[plot]' (or pip install matplotlib)"
        ) from error
    figure = Figure(**options)
    FigureCanvasAgg(figure)
    return figure


def colour_cycle() -> list[str]:
    """The colours of matplotlib's current property cycle (``rcParams``), read, not set."""
    import matplotlib

    return matplotlib.rcParams["axes.prop_cycle"].by_key()["color"]


def colormap(name: str) -> Any:
    """Matplotlib's registered colormap ``name`` (no pyplot involved)."""
    import matplotlib

    return matplotlib.colormaps[name]


def png_bytes(figure: Any) -> bytes:
    """The figure as PNG bytes."""
    image = io.BytesIO()
    figure.savefig(image, format="png", dpi=PNG_DPI, bbox_inches="tight")
    return image.getvalue()


def save_figure(figure: Any, path: str | Path) -> Path:
    """Write ``figure`` as a PNG at ``path`` (parent folders created)."""
    path = Path(path)
    return replace_file(path.parent, path.name, png_bytes(figure))  # never through a link
