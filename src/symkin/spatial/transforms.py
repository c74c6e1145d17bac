"""Homogeneous 4x4 transforms ``[R p; 0 1]`` and a graph of named frames.

``T_a_b`` is the pose of frame b in frame a: ``T_a_b @ [x_b; 1] = [x_a; 1]``.
"""

from __future__ import annotations

import itertools
from collections import deque
from collections.abc import Hashable

import numpy as np
import sympy as sp

from symkin.errors import SymkinError
from symkin.spatial.backend import (
    Matrix,
    MatrixLike,
    as_matrix,
    as_vector,
    backend_of,
    is_symbolic,
    transform_input,
)

# --------------------------------------------------------------------------------------------
# Homogeneous transforms
# --------------------------------------------------------------------------------------------


def transform_from_rotation_translation(R: MatrixLike, p: MatrixLike) -> Matrix:
    """The 4x4 homogeneous transform ``[[R, p], [0 0 0 1]]``.

    ``R`` is a 3x3 rotation and ``p`` a 3-vector (the origin of the child frame expressed in the
    parent frame), so ``T @ [x; 1] = [R x + p; 1]``.
    """
    be = backend_of(R, p)
    Rm = as_matrix(be, R, (3, 3), "R")
    pv = as_vector(be, p, 3, "p")
    rows = [[Rm[i, 0], Rm[i, 1], Rm[i, 2], pv[i]] for i in range(3)]
    return be.matrix([*rows, [0, 0, 0, 1]])


def transform_inverse(T: MatrixLike) -> Matrix:
    """Inverse of a rigid transform in closed form.

    ``[[R, p], [0, 1]]^-1 = [[R^T, -R^T p], [0, 1]]``.

    Never a general matrix inverse: exact for SymPy (no ``1/det``) and cheaper for NumPy.
    Numeric ``T`` must be rigid (rotation block, bottom row ``0 0 0 1``).
    """
    be, M = transform_input(T)
    Rt = M[:3, :3].T
    p = [M[i, 3] for i in range(3)]
    minus_rt_p = [-sum(Rt[i, j] * p[j] for j in range(3)) for i in range(3)]
    return transform_from_rotation_translation(Rt, be.vector(minus_rt_p))


def transform_point(T: MatrixLike, p: MatrixLike) -> Matrix:
    """Apply a homogeneous transform to a 3-vector point: ``R p + t``.

    Returns NumPy shape ``(3,)`` or a SymPy 3x1 matrix.
    """
    be = backend_of(T, p)
    M = as_matrix(be, T, (4, 4), "T")
    pv = as_vector(be, p, 3, "p")
    return be.vector([sum(M[i, j] * pv[j] for j in range(3)) + M[i, 3] for i in range(3)])


# --------------------------------------------------------------------------------------------
# Transform graph
# --------------------------------------------------------------------------------------------


class TransformGraph:
    """Frames as nodes, known transforms as directed edges.

    ``add(parent, child, T_parent_child)`` records the pose of ``child`` in ``parent``.
    ``transform(frm, to)`` returns ``T_frm_to``, the pose of ``to`` in ``frm``: the product of
    the edge transforms along a shortest path (breadth-first search, neighbours visited in the
    order edges were added, so the result is deterministic).  An edge traversed against its
    direction contributes its closed-form :func:`transform_inverse`.

    All state lives in the instance; stored NumPy matrices are read-only copies, so later
    changes to the caller's array do not leak in.  If the path contains a SymPy edge the result
    is SymPy (NumPy edges are converted), otherwise NumPy.
    """

    def __init__(self) -> None:
        # (parent, child) -> T_parent_child
        self._edges: dict[tuple[Hashable, Hashable], Matrix] = {}
        # frame -> neighbours in insertion order (both directions), for deterministic BFS
        self._neighbours: dict[Hashable, list[Hashable]] = {}

    @property
    def frames(self) -> tuple[Hashable, ...]:
        """The known frames, in the order they were first added."""
        return tuple(self._neighbours)

    def __contains__(self, frame: object) -> bool:
        return frame in self._neighbours

    def add(self, parent: Hashable, child: Hashable, T_parent_child: MatrixLike) -> None:
        """Record ``T_parent_child``, the pose of frame ``child`` in frame ``parent``.

        Raises :class:`SymkinError` if ``parent == child``, if the two frames are already
        connected by an edge (either direction; replacing silently would hide a conflict), or if
        ``T_parent_child`` is not a (numerically rigid) 4x4 transform.
        """
        if parent == child:
            raise SymkinError(f"a transform needs two different frames, got {parent!r} twice")
        if (parent, child) in self._edges or (child, parent) in self._edges:
            raise SymkinError(f"frames {parent!r} and {child!r} are already connected")
        _, M = transform_input(T_parent_child, f"T_{parent}_{child}")
        if isinstance(M, np.ndarray):
            M = M.copy()
            M.setflags(write=False)
        self._edges[(parent, child)] = M
        self._neighbours.setdefault(parent, []).append(child)
        self._neighbours.setdefault(child, []).append(parent)

    def transform(self, frm: Hashable, to: Hashable) -> Matrix:
        """``T_frm_to``: the pose of frame ``to`` expressed in frame ``frm``.

        Raises :class:`SymkinError` naming the frames if one is unknown or no chain of
        transforms connects them.  ``transform(a, a)`` is the 4x4 identity (SymPy if the graph
        holds any SymPy edge, else NumPy).
        """
        for frame in (frm, to):
            if frame not in self._neighbours:
                known = ", ".join(repr(f) for f in self._neighbours) or "none"
                raise SymkinError(f"unknown frame {frame!r} (known frames: {known})")
        path = self._path(frm, to)
        if path is None:
            raise SymkinError(f"no chain of transforms connects frame {frm!r} to frame {to!r}")
        factors = []
        for a, b in itertools.pairwise(path):
            if (a, b) in self._edges:
                factors.append(self._edges[(a, b)])
            else:  # the edge is stored as b -> a: walk it backwards
                factors.append(transform_inverse(self._edges[(b, a)]))
        symbolic = any(is_symbolic(f) for f in factors) or (
            not factors and any(is_symbolic(f) for f in self._edges.values())
        )
        if symbolic:
            result = sp.ImmutableMatrix(sp.eye(4))
            for f in factors:
                result = result @ sp.ImmutableMatrix(f)
            return sp.ImmutableMatrix(result)
        result = np.eye(4)
        for f in factors:
            result = result @ f
        return result

    def _path(self, frm: Hashable, to: Hashable) -> list[Hashable] | None:
        """Frames on a shortest path from ``frm`` to ``to`` (inclusive), or None."""
        previous: dict[Hashable, Hashable] = {frm: frm}
        queue = deque([frm])
        while queue:
            node = queue.popleft()
            if node == to:
                path = [node]
                while node != frm:
                    node = previous[node]
                    path.append(node)
                return path[::-1]
            for nxt in self._neighbours[node]:
                if nxt not in previous:
                    previous[nxt] = node
                    queue.append(nxt)
        return None
