"""Sines and cosines of one angle in pairs, for the NumPy backend's ``_sincos``.

NumPy evaluates ``sin`` and ``cos`` of float64 arrays one element at a time (about 10 ns
each), while its ``tan`` loop is vectorised.  The generated module computes both from one
tangent of the half angle (``_sincos`` in ``templates/numpy/module.py.j2``), so the kernel's
``sin(a)`` and ``cos(a)`` are rewritten here into one pair assignment per angle ``a``:
``s, c = _sincos(a)``, placed where the first of the two is needed.  A CSE intermediate that
is exactly ``sin(a)`` or ``cos(a)`` keeps its name.  Angles that hold no symbol, or that
themselves hold a sine or cosine, stay as they are.
"""

from __future__ import annotations

import dataclasses

import sympy as sp

from symkin.kernels import Kernel


@dataclasses.dataclass(frozen=True)
class TrigPair:
    """``sin_name, cos_name = _sincos(angle)``."""

    sin: sp.Symbol
    cos: sp.Symbol
    angle: sp.Expr


def _angles(kernel: Kernel) -> tuple[dict[sp.Expr, int], set[int]]:
    """Each pairable angle and the index of the first assignment that needs it (the number
    of assignments when only an output does), in a deterministic order; and the indices of
    the expressions (assignments, then outputs) that hold a pairable sine or cosine."""
    exprs = [e for _, e in kernel.assignments] + [sp.Tuple(*o.matrix) for o in kernel.outputs]
    first: dict[sp.Expr, int] = {}
    holders: set[int] = set()
    for index, expr in enumerate(exprs):
        found = sorted((t.args[0] for t in expr.atoms(sp.sin, sp.cos)), key=sp.default_sort_key)
        for angle in found:
            if angle.free_symbols and not angle.has(sp.sin, sp.cos):
                first.setdefault(angle, min(index, len(kernel.assignments)))
                holders.add(index)
    return first, holders


def pair_trig(kernel: Kernel) -> tuple[Kernel, dict[int, TrigPair]]:
    """The kernel with every pairable ``sin(a)``/``cos(a)`` replaced by symbols defined in
    consecutive assignments ``(s, sin(a)), (c, cos(a))``, and the pairs by the index of their
    first assignment in the new kernel."""
    first, holders = _angles(kernel)
    named = {
        (type(e), e.args[0]): s for s, e in kernel.assignments if isinstance(e, (sp.sin, sp.cos))
    }
    pairs = []
    for k, angle in enumerate(first):
        sin = named.get((sp.sin, angle), sp.Symbol(f"_s{k}"))
        cos = named.get((sp.cos, angle), sp.Symbol(f"_c{k}"))
        pairs.append(TrigPair(sin, cos, angle))
    mapping = {sp.sin(p.angle): p.sin for p in pairs} | {sp.cos(p.angle): p.cos for p in pairs}
    renamed = set(mapping.values())
    assignments: list[tuple[sp.Symbol, sp.Expr]] = []
    starts: dict[int, TrigPair] = {}
    opened_at: dict[int, list[TrigPair]] = {}
    for pair in pairs:
        opened_at.setdefault(first[pair.angle], []).append(pair)
    for index in range(len(kernel.assignments) + 1):
        for pair in opened_at.get(index, ()):
            starts[len(assignments)] = pair
            assignments += [(pair.sin, sp.sin(pair.angle)), (pair.cos, sp.cos(pair.angle))]
        if index < len(kernel.assignments):
            symbol, expr = kernel.assignments[index]
            if symbol not in renamed:
                assignments.append((symbol, expr.xreplace(mapping) if index in holders else expr))
    n = len(kernel.assignments)
    outputs = tuple(
        dataclasses.replace(o, matrix=o.matrix.xreplace(mapping)) if n + k in holders else o
        for k, o in enumerate(kernel.outputs)
    )
    rewritten = dataclasses.replace(kernel, assignments=tuple(assignments), outputs=outputs)
    return rewritten, starts
