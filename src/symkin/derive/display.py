"""Rich display hooks for Jupyter, filled in by the layers that can draw and print.

A :class:`~symkin.derive.Model` answers IPython's ``_repr_png_`` and ``_repr_latex_``, but
drawing (matplotlib, :mod:`symkin.solve.draw`) and LaTeX printing (:mod:`symkin.emit.latex`)
live in layers above this one; they register their renderer here when imported (``import
symkin`` imports them), so the dependency keeps pointing one way.  Without a renderer the
hook returns None and IPython falls back to the text ``repr``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

_RENDERERS: dict[str, Callable[[Any], Any]] = {}


def register_display(kind: str, renderer: Callable[[Any], Any]) -> None:
    """Use ``renderer(model)`` for the ``kind`` ("png" or "latex") display of a model."""
    _RENDERERS[kind] = renderer


def rich_display(kind: str, model: Any) -> Any:
    """The registered ``kind`` display of ``model``, or None."""
    renderer = _RENDERERS.get(kind)
    return None if renderer is None else renderer(model)
