"""The recursive Newton–Euler pass, symbolic, every intermediate named as it proceeds.

One formulation serves standard and modified DH.  Write ``A_i`` (frame i in frame i-1) with
rotation ``R_i`` and translation ``p_i``; joint i moves about (or along) the unit axis
``a_i`` through the point ``j_i``, both constant in frame i-1: standard DH ``a_i = z``,
``j_i = 0`` (Spong, Luh–Walker–Paul); modified DH ``a_i = Rx(alpha) z``,
``j_i = Rx(alpha) (a, 0, 0)`` (Craig eqs. 6.45-6.53); a flipped joint moves about ``-a_i``
(its ``q_i`` enters the DH table as ``-q_i``).  In frame-i coordinates, with
``s_i = R_i^T a_i`` and ``e_i = R_i^T (p_i - j_i)`` (from the axis point to origin i)::

  revolute:   w_i  = R_i^T w_{i-1} + s_i dq_i
              dw_i = R_i^T dw_{i-1} + s_i ddq_i + (R_i^T w_{i-1}) x s_i dq_i
              dv_i = R_i^T (dv_{i-1} + U_{i-1} j_i) + U_i e_i
  prismatic:  w_i  = R_i^T w_{i-1},  dw_i = R_i^T dw_{i-1}
              dv_i = R_i^T (dv_{i-1} + U_{i-1} p_i) + 2 w_i x s_i dq_i + s_i ddq_i

where ``U_i = [dw_i]x + [w_i]x [w_i]x`` (so ``U x = dw x x + w x (w x x)``, the acceleration
of a point relative to the origin; Khalil & Dombre eq. 9.97), built from the six products
``w_a w_b`` once per link, and ``dv_0 = -g`` (gravity as a base acceleration).  Inward, with
the COM ``r_i``::

  F_i = m_i (dv_i + U_i r_i),   N_i = I_i dw_i + w_i x (I_i w_i)
  f_i = F_i + R_{i+1} f_{i+1}
  m_i = N_i + r_i x F_i + e_i x f_i + R_{i+1} m_{i+1} + j_{i+1} x (R_{i+1} f_{i+1})
  tau_i = s_i . m_i  (revolute),   s_i . f_i  (prismatic)

``w x (I w)`` is written in the same products ``w_a w_b`` (linear in the entries of ``I``),
and the barycentric form (first moment ``mc``, inertia about the origin) reads
``F = m dv + U mc``, ``N = I_o dw + w x (I_o w) + mc x dv`` (eq. 9.98).

``m_i`` is the moment about the joint's axis point ``j_i`` (not about origin i): it is what
``tau`` needs, and carrying it to the parent costs one cross product with the sparse ``j``
(zero in standard DH) instead of one with ``p``.

``M`` comes column by column from ``tau(q, 0, e_j)`` without gravity, ``G`` from
``tau(q, 0, 0)``, ``c`` from ``tau(q, dq, 0)`` without gravity.  The Coriolis matrix ``C``
takes Christoffel symbols of ``M``, differentiating through the named intermediates
(forward mode) so it never expands.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import lru_cache

import sympy as sp

from symkin.derive.dynamics import link_inertial_data
from symkin.derive.kinematics import Kinematics, joint_axis_sign, joint_placement
from symkin.robot import Link, Robot
from symkin.symbols import unused_prefix


@dataclass(frozen=True)
class BarycentricParameters:
    """One link's inertia about its frame origin, first moment ``m c`` and mass (frame-i axes)."""

    inertia: sp.ImmutableMatrix
    first_moment: sp.ImmutableMatrix
    mass: sp.Expr

    @classmethod
    def from_values(cls, values: dict[str, sp.Expr]) -> BarycentricParameters:
        v = values
        return cls(
            inertia=sp.ImmutableMatrix(
                [
                    [v["xx"], v["xy"], v["xz"]],
                    [v["xy"], v["yy"], v["yz"]],
                    [v["xz"], v["yz"], v["zz"]],
                ]
            ),
            first_moment=sp.ImmutableMatrix([v["mx"], v["my"], v["mz"]]),
            mass=v["m"],
        )


def barycentric_definitions(link: Link) -> dict[str, sp.Expr]:
    """Parallel-axis theorem (Khalil & Dombre eq. 9.4): the inertia about the frame origin
    ``I_o = I_c + m (c.c E - c c^T)``, the first moment ``m c`` and ``m``, from the centre-of-mass
    form of ``link`` (tensor elements: ``xy`` is the (1,2) element).  Symbolic or numeric, as
    the link's data are."""
    m = link.mass
    cx, cy, cz = link.com
    ixx, iyy, izz, ixy, ixz, iyz = link.inertia
    return {
        "xx": ixx + m * (cy**2 + cz**2), "yy": iyy + m * (cx**2 + cz**2),
        "zz": izz + m * (cx**2 + cy**2), "xy": ixy - m * cx * cy,
        "xz": ixz - m * cx * cz, "yz": iyz - m * cy * cz,
        "mx": m * cx, "my": m * cy, "mz": m * cz, "m": m,
    }  # fmt: skip


Z_AXIS = sp.Matrix([0, 0, 1])


@dataclass
class Recorder:
    """Names each non-trivial expression ``<prefix><k>`` and keeps the definitions in order."""

    prefix: str
    assignments: list[tuple[sp.Symbol, sp.Expr]] = field(default_factory=list)
    _derivatives: dict[tuple[sp.Symbol, sp.Symbol], sp.Expr] = field(default_factory=dict)
    _definitions: dict[sp.Symbol, sp.Expr] = field(default_factory=dict)

    def name(self, expr: sp.Expr) -> sp.Expr:
        expr = sp.sympify(expr)
        if expr.is_Atom or (expr.is_Mul and len(expr.args) == 2 and expr.args[0] == -1):
            return expr
        symbol = sp.Symbol(f"{self.prefix}{len(self.assignments)}", real=True)
        self.assignments.append((symbol, expr))
        self._definitions[symbol] = expr
        return symbol

    def vector(self, vector: sp.MatrixBase) -> sp.Matrix:
        return sp.Matrix([self.name(e) for e in vector])

    def derivative(self, expr: sp.Expr, variable: sp.Symbol) -> sp.Expr:
        """``d expr / d variable`` through the named intermediates (forward mode)."""
        return self.name(self._chain(expr, variable))

    def _chain(self, expr: sp.Expr, variable: sp.Symbol) -> sp.Expr:
        # One walk of the tree with the chain rule; a named symbol contributes its own
        # (named, cached) derivative.  Sums, products, integer powers, sin and cos cover the
        # recursions; anything else goes through SymPy's diff.
        if expr.is_Symbol:
            if expr == variable:
                return sp.Integer(1)
            if expr in self._definitions:
                return self._derivative_of_symbol(expr, variable)
            return sp.Integer(0)
        if expr.is_Number:
            return sp.Integer(0)
        if expr.is_Add:
            return sp.Add(*(self._chain(a, variable) for a in expr.args))
        if expr.is_Mul:
            args = expr.args
            terms = []
            for k, factor in enumerate(args):
                inner = self._chain(factor, variable)
                if inner != 0:
                    terms.append(sp.Mul(*args[:k], inner, *args[k + 1 :]))
            return sp.Add(*terms)
        if expr.is_Pow and expr.exp.is_Number:
            inner = self._chain(expr.base, variable)
            return expr.exp * expr.base ** (expr.exp - 1) * inner if inner != 0 else inner
        if isinstance(expr, (sp.sin, sp.cos)):
            inner = self._chain(expr.args[0], variable)
            if inner == 0:
                return inner
            outer = sp.cos(expr.args[0]) if isinstance(expr, sp.sin) else -sp.sin(expr.args[0])
            return outer * inner
        total = sp.diff(expr, variable)
        # Sorted: set order follows string hashes, which change with PYTHONHASHSEED.
        named = expr.free_symbols & self._definitions.keys()
        for symbol in sorted(named, key=lambda s: s.name):
            inner = self._derivative_of_symbol(symbol, variable)
            if inner != 0:
                total += sp.diff(expr, symbol) * inner
        return total

    def _derivative_of_symbol(self, symbol: sp.Symbol, variable: sp.Symbol) -> sp.Expr:
        key = (symbol, variable)
        if key not in self._derivatives:
            self._derivatives[key] = self.derivative(self._definitions[symbol], variable)
        return self._derivatives[key]


def robot_recorder(robot: Robot, prefix: str) -> Recorder:
    """A :class:`Recorder` for ``robot`` whose names ``<prefix><k>`` are none of its parameters:
    ``prefix`` with ``_`` appended while a parameter is named ``<prefix><digits>``
    (:func:`symkin.symbols.unused_prefix`; a parameter ``s1`` makes ``s_0, s_1, ...``).  A
    clash would make the intermediate the parameter itself: same name, same assumptions."""
    return Recorder(unused_prefix(prefix, (name for name, _ in robot.parameters)))


@dataclass(frozen=True)
class _JointGeometry:
    revolute: bool
    rotation: sp.Matrix  # R_i
    translation: sp.Matrix  # p_i
    axis: sp.Matrix  # s_i, frame i
    offset: sp.Matrix  # e_i, frame i
    point: sp.Matrix  # j_i, frame i-1


@lru_cache(maxsize=16)
def joint_geometry(robot: Robot, kinematics: Kinematics) -> tuple[_JointGeometry, ...]:
    """Per-joint geometry, simplified once and shared by every recursion of one robot."""
    geometry = []
    for joint, link in zip(robot.joints, kinematics.link_transforms, strict=True):
        rotation, translation = sp.Matrix(link[:3, :3]), sp.Matrix(link[:3, 3])
        if robot.convention == "standard":
            axis, point = Z_AXIS, sp.zeros(3, 1)
        else:  # modified DH and placement: A_i = C_i Rz Tz, the axis is C_i's z axis
            constant = joint_placement(joint, robot.convention)
            axis, point = sp.Matrix(constant[:3, :3]) * Z_AXIS, sp.Matrix(constant[:3, 3])
        axis = joint_axis_sign(joint) * axis
        geometry.append(
            _JointGeometry(
                revolute=joint.type == "revolute",
                rotation=rotation,
                translation=translation,
                axis=sp.simplify(rotation.T * axis),
                offset=sp.simplify(rotation.T * (translation - point)),
                point=point,
            )
        )
    return tuple(geometry)


@dataclass(frozen=True)
class _LinkMotion:
    """Angular velocity and acceleration of a link, the six products ``w_a w_b`` and
    ``U = [dw]x + [w]x [w]x`` (so the acceleration of a point ``x`` is ``dv + U x``), frame i.
    Khalil & Dombre, *Modeling, Identification and Control of Robots*, eq. 9.97."""

    w: sp.Matrix
    dw: sp.Matrix
    products: dict[str, sp.Expr]
    u: sp.Matrix

    @classmethod
    def of(cls, w: sp.Matrix, dw: sp.Matrix, recorder: Recorder) -> _LinkMotion:
        wx, wy, wz = w
        products = {
            "xx": wx * wx, "yy": wy * wy, "zz": wz * wz,
            "xy": wx * wy, "xz": wx * wz, "yz": wy * wz,
        }  # fmt: skip
        p = {k: recorder.name(v) for k, v in products.items()}
        dx, dy, dz = dw
        u = sp.Matrix(
            [
                [-(p["yy"] + p["zz"]), p["xy"] - dz, p["xz"] + dy],
                [p["xy"] + dz, -(p["xx"] + p["zz"]), p["yz"] - dx],
                [p["xz"] - dy, p["yz"] + dx, -(p["xx"] + p["yy"])],
            ]
        )
        return cls(w, dw, p, u.applyfunc(recorder.name))

    def gyroscopic(self, inertia: sp.Matrix) -> sp.Matrix:
        """``w x (I w)`` for a symmetric ``I``, linear in the products ``w_a w_b``."""
        p = self.products
        xx, yy, zz = inertia[0, 0], inertia[1, 1], inertia[2, 2]
        xy, xz, yz = inertia[0, 1], inertia[0, 2], inertia[1, 2]
        return sp.Matrix(
            [
                xz * p["xy"] - xy * p["xz"] + yz * (p["yy"] - p["zz"]) + (zz - yy) * p["yz"],
                xy * p["yz"] - yz * p["xy"] + xz * (p["zz"] - p["xx"]) + (xx - zz) * p["xz"],
                yz * p["xz"] - xz * p["yz"] + xy * (p["xx"] - p["yy"]) + (yy - xx) * p["xy"],
            ]
        )


# The base: at rest (gravity enters as the base's acceleration, not here).
_AT_REST = _LinkMotion(
    sp.ImmutableMatrix.zeros(3, 1),
    sp.ImmutableMatrix.zeros(3, 1),
    {},
    sp.ImmutableMatrix.zeros(3, 3),
)


def _body_wrench(
    link: Link, motion: _LinkMotion, dv: sp.Matrix, recorder: Recorder
) -> tuple[sp.Matrix, sp.Matrix]:
    """Force and moment about the frame origin that move the link (COM form):
    ``F = m (dv + U r)``, ``N = I_c dw + w x (I_c w) + r x F``."""
    com = sp.Matrix(link.com)
    inertia = sp.Matrix(link.inertia_matrix)
    force = recorder.vector(link.mass * (dv + motion.u * com))
    return force, inertia * motion.dw + motion.gyroscopic(inertia) + com.cross(force)


def _barycentric_wrench(
    link: BarycentricParameters, motion: _LinkMotion, dv: sp.Matrix, recorder: Recorder
) -> tuple[sp.Matrix, sp.Matrix]:
    """The same with barycentric parameters (Khalil & Dombre, eq. 9.98):
    ``F = m dv + U mc``, ``N = I_o dw + w x (I_o w) + mc x dv``."""
    first = sp.Matrix(link.first_moment)
    inertia = sp.Matrix(link.inertia)
    force = recorder.vector(link.mass * dv + motion.u * first)
    return force, inertia * motion.dw + motion.gyroscopic(inertia) + first.cross(dv)


def _outward(
    geometry: Sequence[_JointGeometry],
    recorder: Recorder,
    dq: Sequence[sp.Expr],
    ddq: Sequence[sp.Expr],
    dv: sp.Matrix,
) -> list[tuple[_LinkMotion, sp.Matrix]]:
    """The outward pass: each link's motion (``w``, ``dw``, ``U``) and its origin's
    acceleration ``dv`` in its own frame, from the base's ``dv_0 = -g`` (module docstring)."""
    motion = _AT_REST
    states = []
    for i, joint in enumerate(geometry):
        back = joint.rotation.T
        w, dw = motion.w, motion.dw
        if joint.revolute:
            w_parent = back * w
            w_new = recorder.vector(w_parent + joint.axis * dq[i])
            dw_new = recorder.vector(
                back * dw + joint.axis * ddq[i] + w_parent.cross(joint.axis) * dq[i]
            )
            moved = _LinkMotion.of(w_new, dw_new, recorder)
            origin = back * (dv + motion.u * joint.point)
            dv_new = origin + moved.u * joint.offset
        else:
            moved = _LinkMotion.of(recorder.vector(back * w), recorder.vector(back * dw), recorder)
            origin = back * (dv + motion.u * joint.translation)
            dv_new = origin + 2 * moved.w.cross(joint.axis) * dq[i] + joint.axis * ddq[i]
        motion, dv = moved, recorder.vector(dv_new)
        states.append((motion, dv))
    return states


def joint_torques(
    robot: Robot,
    kinematics: Kinematics,
    recorder: Recorder,
    dq: Sequence[sp.Expr],
    ddq: Sequence[sp.Expr],
    gravity: Sequence[sp.Expr],
    inertial: Sequence[BarycentricParameters] | None = None,
    tip: tuple[sp.MatrixBase, sp.MatrixBase] | None = None,
) -> list[sp.Expr]:
    """``tau`` of the rigid bodies for the given joint rates (no friction, no rotor inertia).

    The links carry the robot file's data (mass, centre of mass, inertia about it) unless
    ``inertial`` gives each link's barycentric parameters (the base parameters, say).
    ``tip``: the force and the moment about origin n that the last link exerts on its
    surroundings (frame-n axes), the outer boundary condition ``f_{n+1}, m_{n+1}`` of the
    inward pass (zero when None; see :mod:`symkin.derive.wrench`).
    """
    geometry = joint_geometry(robot, kinematics)
    base_rotation = sp.Matrix(robot.base[:3, :3])
    dv = recorder.vector(-base_rotation.T * sp.Matrix(gravity))
    states = _outward(geometry, recorder, dq, ddq, dv)

    force = sp.zeros(3, 1)
    about_joint = sp.zeros(3, 1)
    torques: list[sp.Expr] = [sp.Integer(0)] * robot.dof
    for i in reversed(range(robot.dof)):
        motion, dv = states[i]
        if inertial is None:
            body_force, body_moment = _body_wrench(
                link_inertial_data(robot, i), motion, dv, recorder
            )
        else:
            body_force, body_moment = _barycentric_wrench(inertial[i], motion, dv, recorder)
        if i + 1 < robot.dof:
            child = geometry[i + 1]
            carried_force = child.rotation * force
            carried_moment = child.rotation * about_joint + child.point.cross(carried_force)
        elif tip is not None:
            carried_force, carried_moment = sp.Matrix(tip[0]), sp.Matrix(tip[1])
        else:
            carried_force = carried_moment = sp.zeros(3, 1)
        force = recorder.vector(body_force + carried_force)
        joint = geometry[i]
        # The moment about the joint's axis point gives tau and, rotated, the parent's load:
        # one cross product per link instead of two (p_i x R f = j_i x R f + R (e_i x f)).
        about_joint = recorder.vector(body_moment + carried_moment + joint.offset.cross(force))
        axis = joint.axis
        torques[i] = recorder.name(axis.dot(about_joint if joint.revolute else force))
    return torques


def _origin_velocities(
    geometry: Sequence[_JointGeometry],
    states: Sequence[tuple[_LinkMotion, sp.Matrix]],
    recorder: Recorder,
    dq: Sequence[sp.Expr],
) -> list[sp.Matrix]:
    """Velocity ``v_i`` of each frame origin in its own frame, from a base at rest::

      revolute:   v_i = R_i^T (v_{i-1} + w_{i-1} x j_i) + w_i x e_i
      prismatic:  v_i = R_i^T (v_{i-1} + w_{i-1} x p_i) + s_i dq_i

    (the axis point moves with link i-1; link i turns about it or slides along ``s_i``).
    """
    velocity = sp.zeros(3, 1)
    w = sp.zeros(3, 1)
    velocities = []
    for i, (joint, (motion, _)) in enumerate(zip(geometry, states, strict=True)):
        back = joint.rotation.T
        if joint.revolute:
            moved = back * (velocity + w.cross(joint.point)) + motion.w.cross(joint.offset)
        else:
            moved = back * (velocity + w.cross(joint.translation)) + joint.axis * dq[i]
        velocity, w = recorder.vector(moved), motion.w
        velocities.append(velocity)
    return velocities


def point_motion_recursion(
    robot: Robot,
    kinematics: Kinematics,
    link: int,
    point: Sequence[sp.Expr],
    recorder: Recorder,
    dq: Sequence[sp.Expr],
    ddq: Sequence[sp.Expr],
) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """Base-frame position, velocity and acceleration of ``point`` (frame ``link``), link by link.

    The outward pass of :func:`joint_torques` without gravity gives ``w``, ``U`` and the
    origin's ``dv`` in the link's frame, :func:`_origin_velocities` its ``v``; then
    ``v_r = v + w x r``, ``a_r = dv + U r`` (Khalil & Dombre eq. 9.97), and the three vectors
    are carried to the base one link transform at a time, ``x <- R_k x (+ p_k)``, k = link..1.
    """
    r = sp.Matrix(point)
    geometry = joint_geometry(robot, kinematics)[:link]
    position = r
    velocity = acceleration = sp.zeros(3, 1)
    if link:
        states = _outward(geometry, recorder, dq, ddq, sp.zeros(3, 1))
        motion, dv = states[-1]
        v = _origin_velocities(geometry, states, recorder, dq)[-1]
        velocity = recorder.vector(v + motion.w.cross(r))
        acceleration = recorder.vector(dv + motion.u * r)
    base = sp.Matrix(kinematics.frame_transforms[0])  # base, trig constants evaluated
    steps = [(g.rotation, g.translation) for g in reversed(geometry)]
    for rotation, translation in [*steps, (base[:3, :3], base[:3, 3])]:
        position = recorder.vector(rotation * position + translation)
        if link:
            velocity = recorder.vector(rotation * velocity)
            acceleration = recorder.vector(rotation * acceleration)
    return position, velocity, acceleration
