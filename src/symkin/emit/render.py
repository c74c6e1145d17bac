"""The one Jinja environment, and the file preamble every generated file starts with."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from functools import cache
from importlib import resources

import jinja2
import numpy
import sympy as sp

from symkin.kernels import Kernel
from symkin.robot import Robot
from symkin.text import printable

REGENERATE_COMMAND = "symkin generate"


@cache
def environment() -> jinja2.Environment:
    """Templates from the ``symkin.templates`` package data (top-level ``templates/``)."""
    root = resources.files("symkin.templates")
    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(root)),
        undefined=jinja2.StrictUndefined,
        keep_trailing_newline=True,
        trim_blocks=True,
        lstrip_blocks=True,
        autoescape=False,
    )
    # ``file_text("c/lib/x.c")``: a file's text as it is, never parsed as a template (real C
    # sources may hold ``{{`` or ``{#``).
    env.globals["file_text"] = lambda name: env.loader.get_source(env, name)[0]
    return env


def render(template: str, **context: object) -> str:
    return environment().get_template(template).render(**context)


def parameter_context(
    robot: Robot, literal: Callable[[float], str], missing: str
) -> dict[str, list[str]]:
    """Parameter names and default values as code literals (``missing`` where none is given;
    a NaN default makes a forgotten value visible instead of silently wrong)."""
    return {
        "parameter_names": [name for name, _ in robot.parameters],
        "parameter_values": [missing if v is None else literal(v) for _, v in robot.parameters],
    }


def forward_dynamics_context(kernels: tuple[Kernel, ...]) -> dict[str, object] | None:
    """What the forward-dynamics template needs, or ``None`` without dynamics kernels.

    Forward dynamics takes M and the torques at ``ddq = 0`` from the ``mass_matrix_bias``
    kernel (one CSE, sin and cos shared), which the dynamics kernels always include; ``pi`` is
    the number of inertial symbols they take (0: the file gives all the data);
    ``derivatives`` is 1 when the ``inverse_dynamics_derivatives`` kernel is there too, so
    the forward dynamics' derivatives are composed as well (``-M^-1 dtau/dx``, ``M^-1``).
    ``elastic``: 0-based indices of the elastic joints, whose 2n-state forward dynamics also
    uses ``elastic_constants`` (empty for a rigid robot: no elastic code is printed).
    """
    names = {k.name: k for k in kernels}
    if not {"mass_matrix", "mass_matrix_bias", "inverse_dynamics"} <= names.keys():
        return None
    inputs = {i.name: i for i in names["inverse_dynamics"].inputs}
    elastic: list[int] = []
    if "elastic_constants" in names:
        stiffness = names["elastic_constants"].outputs[0].matrix
        elastic = [i for i, k in enumerate(stiffness) if k != 0]
    return {
        "pi": len(inputs["pi"].symbols) if "pi" in inputs else 0,
        "derivatives": int("inverse_dynamics_derivatives" in names),
        "elastic": elastic,
    }


def number_text(value: sp.Expr) -> str:
    """A number as its shortest decimal (``-9.81``, ``0``); an expression as SymPy prints it."""
    if value.is_Number:
        return numpy.format_float_positional(float(value), trim="-")
    return str(value)


def dynamics_notes(robot: Robot, kernels: tuple[Kernel, ...]) -> list[str]:
    """Where the dynamics kernels take gravity and inertial data from (none without them)."""
    if not any(k.name == "gravity" for k in kernels):
        return []
    gravity = ", ".join(number_text(g) for g in robot.gravity)
    symbols = sorted({s.name for g in robot.gravity for s in g.free_symbols})
    given = [i for i, joint in enumerate(robot.joints, start=1) if joint.link is not None]
    missing = [i for i in range(1, robot.dof + 1) if i not in given]
    where = [f"compiled in for links {', '.join(map(str, given))}"] if given else []
    where += [f"passed as pi for links {', '.join(map(str, missing))}"] if missing else []
    return [
        f"Gravity: ({gravity}) m/s^2 in the base frame"
        + (f", with {', '.join(symbols)} from p." if symbols else ", compiled in."),
        f"Inertial data (mass, centre of mass, inertia): {'; '.join(where)}.",
    ]


def counts_text(kernel: Kernel) -> str:
    """``"12 ops (4 additions, 6 multiplications, 2 trig)"``, zero kinds left out."""
    counts = kernel.operation_counts
    kinds = ", ".join(f"{v} {k}" for k, v in counts.items() if k != "total" and v)
    return f"{counts['total']} ops ({kinds or 'none'})"


def comment_text(text: str) -> str:
    """``text`` on one line, safe inside a C block comment, a Python docstring, a Makefile
    comment and a TeX comment: only printable characters (no line break, NUL or bidirectional
    control), no ``*/``, no triple quote, no backslash (an escape, or a line continuation)."""
    one_line = " ".join(printable(text).split())
    return (
        one_line.replace("*/", "* /").replace("/*", "/ *").replace('"""', "'''").replace("\\", "/")
    )


def preamble_lines(
    robot: Robot, kernels: tuple[Kernel, ...], what: str, flags: Sequence[str] = ()
) -> list[str]:
    """Source, regeneration command and operation counts; no dates, versions or paths.

    ``flags`` are the front end's options that shaped the files (precision, backends, folded
    parameters, points), as it spells them; they end the regeneration command.
    """
    source = comment_text(robot.file or f"robot '{robot.name}' built in Python")
    built_in = robot.file == f"robots/{robot.name}.toml"
    options = "".join(f" {comment_text(flag)}" for flag in flags)
    if built_in and not flags:
        regenerate = f"{REGENERATE_COMMAND}  (or: symkin derive {robot.name} --out DIR)"
    else:
        name = robot.name if built_in else comment_text(robot.file or "ROBOT")
        regenerate = f"symkin derive {name} --out DIR{options}"
    lines = [
        f"{what} for robot '{robot.name}' ({comment_text(robot.title) or 'no title'}).",
        f"Generated by symkin from {source}; do not edit.",
        f"Regenerate with: {regenerate}",
        "Operation counts after common-subexpression elimination:",
    ]
    lines += [f"  {k.name}: {counts_text(k)}" for k in kernels]
    return lines
