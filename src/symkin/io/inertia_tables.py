"""Inertial data from a shape, and the ``[payload]`` table (docs/robot-files.md).

A link (or the payload) may give its inertia by a simple solid instead of a tensor::

    shape = { type = "cylinder", radius = 0.05, length = 0.4, axis = "x" }
    density = 2700          # kg/m^3; or mass = ..., not both

The solid is homogeneous and centred on ``com``, its axes along the frame's (a cylinder's or
tube's axis along ``axis``); the tensors are those of :mod:`symkin.spatial.inertia`.

``[payload]`` (``mass``, ``com``, ``inertia`` or ``shape``, in the **tool** frame) is a rigid
body held by the last link: it is composed with the last link's data (mass added, centre and
tensor about the common centre, Steiner) into that link, so every method and backend sees it.
Values may be parameters, so the payload can change at evaluation time (``--set``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

import sympy as sp

from symkin.io.context import Context, as_table, check_keys, read_choice, show
from symkin.io.expressions import numeric_value, sympy_value
from symkin.robot import Joint, Link
from symkin.spatial.inertia import (
    RigidBody,
    box_inertia,
    box_volume,
    composite_body,
    cylinder_volume,
    hollow_cylinder_inertia,
    rotated_inertia,
    sphere_inertia,
    sphere_volume,
)

SHAPE_TYPES = ("cylinder", "tube", "box", "sphere")
SHAPE_KEYS = {
    "cylinder": ("type", "radius", "length", "axis"),
    "tube": ("type", "inner_radius", "outer_radius", "length", "axis"),
    "box": ("type", "size"),
    "sphere": ("type", "radius"),
}


def _positive(table: dict[str, Any], key: str, ctx: Context) -> sp.Expr:
    if key not in table:
        raise ctx.error(f"{ctx.key(key)!r} is missing")
    value = sympy_value(table[key], key, ctx)
    number = numeric_value(value, ctx)
    if number is not None and number <= 0:
        raise ctx.error(f"{ctx.key(key)!r} must be > 0 (a length), got {number:g}")
    return value


def _solid(table: dict[str, Any], ctx: Context) -> tuple[sp.Expr, Callable[[sp.Expr], Any]]:
    """The volume of the shape and its tensor as a function of the mass."""
    if "type" not in table:
        raise ctx.error(f"{ctx.key('type')!r} is missing; one of {', '.join(SHAPE_TYPES)}")
    kind = read_choice(table, "type", SHAPE_TYPES, ctx)
    check_keys(table, SHAPE_KEYS[kind], ctx)
    if kind == "box":
        size = table.get("size")
        if not isinstance(size, list) or len(size) != 3:
            raise ctx.error(
                f"{ctx.key('size')!r} must be a list of 3 edge lengths, got {show(size)}"
            )
        edges = {f"size[{i}]": v for i, v in enumerate(size)}
        a, b, c = (_positive(edges, f"size[{i}]", ctx) for i in range(3))
        return box_volume(a, b, c), lambda m: box_inertia(m, a, b, c)
    if kind == "sphere":
        r = _positive(table, "radius", ctx)
        return sphere_volume(r), lambda m: sphere_inertia(m, r)
    axis = read_choice(table, "axis", ("z", "x", "y"), ctx)
    length = _positive(table, "length", ctx)
    if kind == "cylinder":
        inner, outer = sp.Integer(0), _positive(table, "radius", ctx)
    else:
        inner, outer = _positive(table, "inner_radius", ctx), _positive(table, "outer_radius", ctx)
        numbers = numeric_value(inner, ctx), numeric_value(outer, ctx)
        if None not in numbers and numbers[0] >= numbers[1]:
            raise ctx.error(f"{ctx.key('inner_radius')!r} must be less than 'outer_radius'")
    volume = cylinder_volume(outer, length, inner)
    return volume, lambda m: hollow_cylinder_inertia(m, inner, outer, length, axis)


def mass_and_inertia_from_shape(
    table: dict[str, Any], ctx: Context
) -> tuple[sp.Expr, tuple[sp.Expr, ...]]:
    """``(mass, (ixx, iyy, izz, ixy, ixz, iyz))`` of a table with ``shape`` and ``density`` or
    ``mass``; ``ctx`` is inside the link (or payload) table."""
    if "inertia" in table:
        raise ctx.error(f"give {ctx.key('inertia')!r} or {ctx.key('shape')!r}, not both")
    if ("mass" in table) == ("density" in table):
        raise ctx.error(f"a {ctx.key('shape')!r} needs 'mass' or 'density' (one of them)")
    volume, tensor_of = _solid(as_table(table["shape"], "shape", ctx), ctx.within("shape"))
    if "mass" in table:
        mass = sympy_value(table["mass"], "mass", ctx)
    else:
        mass = sympy_value(table["density"], "density", ctx) * volume
    number = numeric_value(mass, ctx)
    if number is not None and number < 0:
        raise ctx.error(f"{ctx.key('density')!r} must be >= 0, got a mass of {number:g}")
    tensor = tensor_of(mass)
    elements = (tensor[0, 0], tensor[1, 1], tensor[2, 2], tensor[0, 1], tensor[0, 2], tensor[1, 2])
    return mass, elements


def joints_with_payload(
    joints: tuple[Joint, ...],
    payload: Link,
    tool: sp.MatrixBase,
    ctx: Context,
) -> tuple[Joint, ...]:
    """``joints`` with ``payload`` (tool-frame data) composed into the last link."""
    last = joints[-1]
    if last.link is None:
        raise ctx.error(
            "'payload' needs the last joint's [joints.link] data to add to (its mass, com and "
            "inertia)"
        )
    rotation, origin = sp.Matrix(tool[:3, :3]), sp.Matrix(tool[:3, 3])
    carried = RigidBody(
        payload.mass,
        sp.ImmutableMatrix(rotation * sp.Matrix(payload.com) + origin),
        rotated_inertia(payload.inertia_matrix, rotation),
    )
    link = last.link
    own = RigidBody(link.mass, sp.ImmutableMatrix(link.com), link.inertia_matrix)
    body = composite_body([own, carried])
    i = body.inertia
    combined = replace(
        link,
        mass=body.mass,
        com=tuple(body.com),
        inertia=(i[0, 0], i[1, 1], i[2, 2], i[0, 1], i[0, 2], i[1, 2]),
    )
    return (*joints[:-1], replace(last, link=combined))
