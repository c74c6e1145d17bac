"""The files of the LaTeX derivation: the standalone document, snippets and macros.

:func:`latex_files` takes the content (:func:`symkin.kernels.document.document_content`),
lays out its sections (:mod:`symkin.emit.latex.sections`) and renders the templates
``latex/document.tex.j2``, ``latex/snippet.tex.j2`` and ``latex/macros.tex.j2``.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence

import sympy as sp

from symkin.derive import Model
from symkin.derive.dynamics import link_inertial_data
from symkin.emit.latex.layout import TEXT_WIDTH_CM, UNITS_PER_CM, Layout, gather, pack
from symkin.emit.latex.printer import KinematicsLatexPrinter
from symkin.emit.latex.prose import check_language, prose
from symkin.emit.latex.sections import DIGIT_WORDS, Quantity, Section, SectionWriter
from symkin.emit.render import comment_text, render
from symkin.errors import ParameterError
from symkin.kernels.document import (
    DEFAULT_SECTIONS,
    SECTIONS,
    DocumentContent,
    check_configuration,
    check_sections,
    document_content,
)
from symkin.robot import Robot
from symkin.text import printable

MIN_TEXT_WIDTH_CM, MAX_TEXT_WIDTH_CM = 8.0, 40.0


def macro_prefix(name: str) -> str:
    """A robot name as letters only (``puma560`` -> ``pumaFiveSixZero``) for macro names."""
    out, upper = [], False
    for char in name:
        if char.isdigit():
            out.append(DIGIT_WORDS[int(char)])
        elif char.isalpha():
            out.append(char.upper() if upper else char)
            upper = False
        else:
            upper = True
    return "".join(out)


def inertial_symbol_names(robot: Robot) -> dict[sp.Symbol, str]:
    """How the inertial symbols of links without data print: ``m_{1}``, ``c_{x,1}``,
    ``I_{xx,1}`` (``link_inertial_data`` names them ``m1``, ``cx1``, ``ixx1``)."""
    names: dict[sp.Symbol, str] = {}
    for index, joint in enumerate(robot.joints):
        if joint.link is not None:
            continue
        link, i = link_inertial_data(robot, index), index + 1
        names[link.mass] = f"m_{{{i}}}"
        for axis, c in zip("xyz", link.com, strict=True):
            names[c] = f"c_{{{axis},{i}}}"
        for axes, entry in zip(("xx", "yy", "zz", "xy", "xz", "yz"), link.inertia, strict=True):
            names[entry] = f"I_{{{axes},{i}}}"
    return names


def _check_shorthand_names(model: Model) -> None:
    clash = [s.name for s in model.robot.parameter_symbols if re.fullmatch(r"[cs]_?\d+", s.name)]
    if clash:
        raise ParameterError(
            f"{{shorthand}}: parameter(s) {', '.join(clash)} would read like the abbreviations "
            "c_i, s_i of cosines and sines; rename them or leave out {shorthand}"
        )


def _check_text_width(text_width_cm: float) -> None:
    if not MIN_TEXT_WIDTH_CM <= text_width_cm <= MAX_TEXT_WIDTH_CM:
        raise ParameterError(
            f"{{text_width_cm}} must be from {MIN_TEXT_WIDTH_CM:g} to {MAX_TEXT_WIDTH_CM:g} cm, "
            f"got {text_width_cm:g}"
        )


def _layout(model: Model, shorthand: bool, lang: str, text_width_cm: float) -> Layout:
    """A layout with a fresh printer: its record of abbreviations becomes the legend."""
    if shorthand:
        _check_shorthand_names(model)
    printer = KinematicsLatexPrinter(
        model.q,
        model.dq,
        model.ddq,
        shorthand=shorthand,
        decimal_separator="comma" if lang == "de" else "period",
        symbol_names=inertial_symbol_names(model.robot),
    )
    return Layout(printer, decimal_comma=lang == "de", width=text_width_cm * UNITS_PER_CM)


def configuration_text(content: DocumentContent, layout: Layout, t: Mapping[str, str]) -> str:
    """``q*`` (revolute joints also in degrees) and the parameter values; empty without."""
    if content.q is None:
        return ""
    items = []
    for i, (joint, value) in enumerate(zip(content.model.robot.joints, content.q, strict=True), 1):
        text = f"q_{{{i}}}^{{*}} = {layout.number(value)}"
        if joint.type == "revolute":
            text += rf" = {layout.number(math.degrees(value))}^{{\circ}}"
        items.append(text)
    lines = pack(items, r",\quad ", layout.width)
    parameters = ""
    if content.parameter_values:
        values = [f"{layout.tex(s)} = {layout.number(v)}" for s, v in content.parameter_values]
        parameters = t["parameters_values"] + "\n" + gather(pack(values, r",\quad ", layout.width))
    return t["configuration"] + "\n" + gather(lines) + "\n" + parameters


def legend_text(layout: Layout, t: Mapping[str, str]) -> str:
    """The abbreviations printed so far with their definitions; empty if none."""
    legend = layout.printer.legend()
    if not legend:
        return ""
    items = [f"{abbreviation} = {definition}" for abbreviation, definition in legend]
    return t["legend"] + "\n" + gather(pack(items, r",\quad ", layout.width))


def header_lines(model: Model, what: str, command: str) -> list[str]:
    """The comment lines heading each file (made safe by :func:`comment_text`: a newline in a
    title would otherwise leave the ``%`` comment and run as TeX)."""
    robot = model.robot
    source = comment_text(robot.file or f"robot '{robot.name}' built in Python")
    return [
        f"{what} for robot '{robot.name}' ({comment_text(robot.title) or 'no title'}).",
        f"Generated by symkin from {source}; do not edit.",
        f"Regenerate with: {comment_text(command)}",
    ]


def regenerate_command(
    model: Model,
    sections: Sequence[str],
    shorthand: bool,
    lang: str,
    q: Sequence[float] | None,
    overrides: Mapping[str, float] | None,
) -> str:
    """The ``symkin latex`` command line that writes these files again (for the header)."""
    parts = ["symkin latex", model.robot.name]
    if shorthand:
        parts.append("--shorthand")
    if lang != "en":
        parts.append(f"--lang {lang}")
    if q is not None:
        parts.append("--q " + ",".join(repr(float(v)) for v in q))
    for name, value in sorted((overrides or {}).items()):
        parts.append(f"--set {name}={float(value)!r}")
    if tuple(sections) != SECTIONS:
        parts.append("--sections " + ",".join(sections))
    return " ".join(parts)


def latex_files(
    model: Model,
    *,
    sections: Sequence[str] = DEFAULT_SECTIONS,
    shorthand: bool = False,
    lang: str = "en",
    q: Sequence[float] | None = None,
    overrides: Mapping[str, float] | None = None,
    text_width_cm: float = TEXT_WIDTH_CM,
) -> dict[str, str]:
    """The LaTeX derivation of ``model``: standalone document, snippets and macros.

    ``sections`` are names from :data:`~symkin.kernels.document.SECTIONS` (``dynamics``: the
    equations of motion by Lagrange, printed up to three joints); ``shorthand`` prints
    ``c_{1}``, ``s_{12}`` with a legend; ``lang`` is ``"en"`` or ``"de"``; ``q`` (radians /
    metres) adds numbers at that configuration, with parameter values from the robot file
    updated by ``overrides``. Formulas are laid out for a line of ``text_width_cm`` (17 cm: A4
    with 2 cm margins; give the host document's ``\\textwidth`` when the snippets go into
    narrower notes). Returns ``{"<robot>.tex", "<robot>-macros.tex",
    "snippets/<quantity>.tex": text}``.
    """
    t = prose(check_language(lang))
    chosen = check_sections(sections)
    q = check_configuration(model, q, overrides)
    _check_text_width(text_width_cm)
    layout = _layout(model, shorthand, lang, text_width_cm)
    content = document_content(model, chosen, q, overrides)
    built = SectionWriter(content, layout, t).build()
    configuration = configuration_text(content, layout, t)
    legend = legend_text(layout, t)  # last: every abbreviation has been printed by now
    command = regenerate_command(model, chosen, shorthand, lang, q, overrides)
    document = _document(model, t, text_width_cm, command, configuration, legend, built)
    quantities = [quantity for section in built for quantity in section.quantities]
    if legend:
        quantities.insert(0, Quantity("legend", "Legend", "the abbreviations", legend))
    if configuration:
        quantities.insert(
            0,
            Quantity(
                "configuration", "Configuration", "q* and the parameter values", configuration
            ),
        )
    files = {f"{model.robot.name}.tex": document}
    files.update(_snippets_and_macros(model, command, quantities))
    return dict(sorted(files.items()))


def _document(
    model: Model,
    t: Mapping[str, str],
    text_width_cm: float,
    command: str,
    configuration: str,
    legend: str,
    sections: list[Section],
) -> str:
    robot = model.robot
    intro = t["intro_placement" if robot.convention == "placement" else "intro"].format(
        name=robot.name.replace("_", r"\_"),
        convention=t[robot.convention],
        dof=robot.dof,
    )
    geometry = (
        "a4paper,margin=2cm"
        if text_width_cm == TEXT_WIDTH_CM
        else f"a4paper,textwidth={text_width_cm:g}cm,vmargin=2cm"
    )
    # The German title is German (issue 21); the robot's own title follows as a subtitle.
    names = {
        "name": robot.name.replace("_", r"\_"),
        "title": escape_text(robot.title or robot.name),
    }
    return render(
        "latex/document.tex.j2",
        geometry=geometry,
        header=header_lines(model, "LaTeX derivation", command),
        title=t["title"].format(name=names["name"], title=names["title"]),
        subtitle=t["subtitle"].format(name=names["name"], title=names["title"]),
        intro=intro,
        configuration=configuration,
        legend=legend,
        sections=sections,
    )


def _snippets_and_macros(
    model: Model, command: str, quantities: Sequence[Quantity]
) -> dict[str, str]:
    """``snippets/<key>.tex`` per quantity and ``<robot>-macros.tex`` with one macro each."""
    files = {}
    for quantity in quantities:
        files[f"snippets/{quantity.key}.tex"] = render(
            "latex/snippet.tex.j2",
            header=header_lines(model, f"LaTeX snippet '{quantity.key}'", command),
            body=quantity.body,
        )
    prefix = macro_prefix(model.robot.name)
    files[f"{model.robot.name}-macros.tex"] = render(
        "latex/macros.tex.j2",
        header=header_lines(model, "LaTeX macros", command),
        macros=[
            {"name": prefix + q.macro, "description": q.description, "body": q.body}
            for q in quantities
        ],
    )
    return files


def escape_text(text: str) -> str:
    """Plain text for LaTeX (robot titles): unprintable characters as visible escapes, then
    TeX's special characters as text."""
    text = printable(text)
    replacements = {
        "\\": r"\textbackslash{}",
        "&": r"\&",
        "%": r"\%",
        "$": r"\$",
        "#": r"\#",
        "_": r"\_",
        "{": r"\{",
        "}": r"\}",
        "~": r"\textasciitilde{}",
        "^": r"\textasciicircum{}",
    }
    return "".join(replacements.get(c, c) for c in text)
