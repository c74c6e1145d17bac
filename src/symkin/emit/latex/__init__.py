"""LaTeX backend: the derivation of a robot's kinematics as a lecture would write it.

:func:`latex_files` returns ``{relative path: text}`` and writes nothing:

* ``<robot>.tex``: a standalone A4 document (DH table, link transforms, the product built up
  step by step, tool position, Z-Y-X Euler angles, Jacobian column by column, determinant,
  singular configurations, inverse Jacobian as adjugate over determinant; on request the
  equations of motion by Lagrange);
* ``snippets/<quantity>.tex``: the same displays, one file per quantity, for ``\\input``;
* ``<robot>-macros.tex``: one ``\\newcommand`` per quantity.

What is shown is decided by :mod:`symkin.kernels.document`; how it is laid out here:
:mod:`~symkin.emit.latex.layout` (whether a matrix fits the line, which entries get names,
where a long entry breaks), :mod:`~symkin.emit.latex.sections` (each section's displays),
:mod:`~symkin.emit.latex.document` (the files), :mod:`~symkin.emit.latex.printer` (symbols and
abbreviations), :mod:`~symkin.emit.latex.prose` (the words, from ``templates/latex/prose``).
"""

from symkin.emit.latex.document import inertial_symbol_names, latex_files, macro_prefix
from symkin.emit.latex.layout import TEXT_WIDTH_CM
from symkin.emit.latex.prose import LANGUAGES
from symkin.kernels.document import DEFAULT_SECTIONS, SECTIONS, check_sections

__all__ = [
    "DEFAULT_SECTIONS",
    "LANGUAGES",
    "SECTIONS",
    "TEXT_WIDTH_CM",
    "check_sections",
    "inertial_symbol_names",
    "latex_files",
    "macro_prefix",
]
