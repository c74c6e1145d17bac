"""Matplotlib, loaded on demand for the PNG plots (IK solutions, paths, optimal trajectories).

Plots are an extra (``pip install symkin[plot]``): the core never imports matplotlib.
"""

from __future__ import annotations

import io
from pathlib import Path
from types import ModuleType

from symkin.errors import SymkinError
from symkin.output_folder import replace_file


def pyplot() -> ModuleType:
    """``matplotlib.pyplot`` with the file-only Agg backend (no screen needed)."""
    try:
        import matplotlib
    except ImportError as error:
        raise SymkinError(
            "plots need matplotlib: pip install 'symkin[plot]' (or pip install matplotlib)"
        ) from error
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save_figure(figure: object, path: str | Path) -> Path:
    """Write ``figure`` as a PNG at ``path`` (parent folders created) and close it."""
    path = Path(path)
    plt = pyplot()
    image = io.BytesIO()
    try:
        figure.savefig(image, format="png", dpi=110, bbox_inches="tight")
    finally:
        plt.close(figure)
    return replace_file(path.parent, path.name, image.getvalue())  # never through a link
