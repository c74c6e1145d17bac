"""The one place symkin mints its symbols: joint variables, parameters, link inertial data.

Every symbol is real.  Names are code-safe (``q1``, ``dq1``, ``ddq1``, ``m1``, ``ixx1``);
LaTeX decoration is the LaTeX printer's job.  Two symbols with the same name and assumptions
are the same SymPy symbol, so minting here once keeps every stage speaking of one ``q1``.
"""

from __future__ import annotations

from collections.abc import Iterable

import sympy as sp

#: Inertial data of link i: mass, centre of mass, inertia about it (xx yy zz xy xz yz).
INERTIAL_NAMES = ("m", "cx", "cy", "cz", "ixx", "iyy", "izz", "ixy", "ixz", "iyz")


def joint_symbols(n: int, prefix: str = "q") -> tuple[sp.Symbol, ...]:
    """Joint variables ``q1..qn`` (or ``dq1..``, ``ddq1..`` with another prefix), real."""
    return tuple(sp.Symbol(f"{prefix}{i}", real=True) for i in range(1, n + 1))


def parameter_symbol(name: str) -> sp.Symbol:
    """A robot file's named parameter (a length, an angle offset), real."""
    return sp.Symbol(name, real=True)


def link_inertial_symbols(number: int) -> dict[str, sp.Symbol]:
    """``{"m": m<number>, "cx": cx<number>, ..., "iyz": iyz<number>}`` for link ``number``
    (1-based).  Masses are positive and principal moments non-negative, which lets SymPy
    simplify ``sqrt(m1**2)`` and the like."""
    assumptions = {"m": {"positive": True}} | {
        name: {"nonnegative": True} for name in ("ixx", "iyy", "izz")
    }
    return {
        name: sp.Symbol(f"{name}{number}", real=True, **assumptions.get(name, {}))
        for name in INERTIAL_NAMES
    }


def unused_prefix(prefix: str, names: Iterable[str]) -> str:
    """``prefix``, with ``_`` appended until no name is ``<prefix><digits>``: a safe prefix
    for numbered intermediates next to the robot's own symbols."""
    names = set(names)
    while any(n.startswith(prefix) and n[len(prefix) :].isdigit() for n in names):
        prefix += "_"
    return prefix


#: Components of the external wrench on the tool: force, then moment (base frame, at the tool
#: point; docs/conventions.md, External wrench).
WRENCH_NAMES = ("w_fx", "w_fy", "w_fz", "w_nx", "w_ny", "w_nz")


def wrench_symbols() -> tuple[sp.Symbol, ...]:
    """``(w_fx, w_fy, w_fz, w_nx, w_ny, w_nz)``: the wrench ``w = (f, n)`` acting on the tool."""
    return tuple(sp.Symbol(name, real=True) for name in WRENCH_NAMES)
