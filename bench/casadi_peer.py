"""An independent CasADi model of a DH robot, written from its table as a CasADi user would.

This is the benchmarks' CasADi peer that does *not* go through symkin's derivation: it reads
only the numbers of a :class:`symkin.robot.Robot` (DH rows, base and tool, gravity, inertial
data; every parameter substituted by its value) and builds, in CasADi ``SX``:

* **FK**: ``T = base · A_1 ⋯ A_n · tool``, with ``A_i = Rz(θ) Tz(d) Tx(a) Rx(α)`` (standard DH)
  or ``Rx(α) Tx(a) Rz(θ) Tz(d)`` (modified DH, Craig), a plain product of 4x4 matrices;
* **the geometric Jacobian** ``[z × (p − o); z]`` (revolute) or ``[z; 0]`` (prismatic) per joint,
  every vector in the base frame, from the same products;
* **inverse dynamics** by the recursive Newton–Euler algorithm in link frames (Siciliano et al.,
  *Robotics: Modelling, Planning and Control*, 2009, Sec. 7.5; Craig, *Introduction to
  Robotics*, Sec. 6.5, for modified DH), plus the reflected rotor inertias ``I_a ddq``;
* **forward dynamics**: ``M`` by ``n`` Newton–Euler passes with a unit joint acceleration and no
  gravity or velocity, the bias ``c + G`` by one pass at ``ddq = 0``, and
  ``ddq = casadi.solve(M, tau − bias)`` (CasADi's own dense solve; on ``SX`` it unrolls a QR
  factorisation without pivoting).  ``M`` is never inverted.

The functions take ``(q, p)`` and ``(q, dq, x, p)`` like symkin's generated CasADi module so that
the same C harness calls both; ``p`` (the robot's parameters) is an unused input here, the
geometry being numeric.  Revolute joints only for the dynamics; friction, elastic joints,
flipped joints and placement-convention robots are refused.  No symkin derivation, kernel or
emitter is imported: agreement with symkin is a check, not a construction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

NAMES = {
    "fk": (("q", "p"), ("T",)),
    "fk_jacobian": (("q", "p"), ("T", "J")),
    "inverse_dynamics": (("q", "dq", "ddq", "p"), ("tau",)),
    "forward_dynamics": (("q", "dq", "tau", "p"), ("ddq",)),
}


class PeerError(ValueError):
    """The robot has a feature this peer does not model."""


@dataclass(frozen=True)
class Row:
    """One joint as numbers: its DH row, whether it is revolute, and its link's data."""

    theta: float
    d: float
    a: float
    alpha: float
    revolute: bool
    mass: float = 0.0
    com: tuple[float, float, float] = (0.0, 0.0, 0.0)
    inertia: np.ndarray | None = None  # 3x3 about the centre of mass, frame-i axes
    rotor: float = 0.0


def _number(expr, values: dict) -> float:
    import sympy as sp

    return float(sp.sympify(expr).xreplace(values))


def _link_data(link, number) -> dict:
    """Mass, centre of mass, inertia tensor and rotor inertia of one link, as numbers."""
    if link is None:
        return {}
    moving = (link.coulomb, link.viscous)
    if any(number(e) != 0 for e in moving) or link.stiffness is not None:
        raise PeerError("the CasADi peer has no friction and no elastic joints")
    ixx, iyy, izz, ixy, ixz, iyz = (number(e) for e in link.inertia)
    return {
        "mass": number(link.mass),
        "com": tuple(number(e) for e in link.com),
        "inertia": np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]]),
        "rotor": number(link.motor_inertia),
    }


def read_table(robot) -> tuple[str, list[Row], np.ndarray, np.ndarray, np.ndarray]:
    """``(convention, rows, base, tool, gravity)`` of ``robot``, every symbol by its value."""
    import sympy as sp

    if robot.convention not in ("standard", "modified"):
        raise PeerError(f"the CasADi peer reads DH tables, not {robot.convention!r} robots")
    values = {sp.Symbol(k, real=True): v for k, v in robot.parameter_values().items()}

    def number(expr) -> float:
        return _number(expr, values)

    rows = []
    for joint in robot.joints:
        if joint.flip or joint.placement is not None:
            raise PeerError("the CasADi peer has no flipped or placed joints")
        rows.append(
            Row(
                *(number(getattr(joint, key)) for key in ("theta", "d", "a", "alpha")),
                revolute=joint.type == "revolute",
                **_link_data(joint.link, number),
            )
        )
    base = np.array([[number(e) for e in row] for row in robot.base.tolist()])
    tool = np.array([[number(e) for e in row] for row in robot.tool.tolist()])
    gravity = np.array([number(g) for g in robot.gravity])
    return robot.convention, rows, base, tool, gravity


def _rot_x(alpha: float):
    import casadi as ca

    c, s = math.cos(alpha), math.sin(alpha)
    return ca.DM([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]])


def _rot_z(theta):
    import casadi as ca

    c, s = ca.cos(theta), ca.sin(theta)
    zero = ca.SX(0)
    return ca.vertcat(
        ca.horzcat(c, -s, zero, zero),
        ca.horzcat(s, c, zero, zero),
        ca.horzcat(zero, zero, 1, zero),
        ca.horzcat(zero, zero, zero, 1),
    )


def _translate(x: float, z) -> object:
    import casadi as ca

    T = ca.SX.eye(4)
    T[0, 3] = x
    T[2, 3] = z
    return T


def joint_transform(convention: str, row: Row, qi):
    """``A_i`` of one row at joint value ``qi``: the DH product of elementary transforms."""
    theta = qi + row.theta if row.revolute else row.theta
    d = row.d if row.revolute else qi + row.d
    if convention == "standard":
        return _rot_z(theta) @ _translate(0.0, d) @ _translate(row.a, 0.0) @ _rot_x(row.alpha)
    return _rot_x(row.alpha) @ _translate(row.a, 0.0) @ _rot_z(theta) @ _translate(0.0, d)


def kinematics(robot, q):
    """``(T, J)``: the tool pose (4x4) and the geometric Jacobian (6 x n), base frame."""
    import casadi as ca

    convention, rows, base, tool, _ = read_table(robot)
    T = ca.SX(ca.DM(base))
    axes = []  # (z, o) of every joint axis, base frame
    for i, row in enumerate(rows):
        if convention == "standard":  # joint i turns about z_{i-1} through o_{i-1}
            axes.append((T[:3, 2], T[:3, 3]))
            T = T @ joint_transform(convention, row, q[i])
        else:  # modified: about z_i through o_i
            T = T @ joint_transform(convention, row, q[i])
            axes.append((T[:3, 2], T[:3, 3]))
    T = T @ ca.DM(tool)
    columns = []
    for row, (z, o) in zip(rows, axes, strict=True):
        if row.revolute:
            columns.append(ca.vertcat(ca.cross(z, T[:3, 3] - o), z))
        else:
            columns.append(ca.vertcat(z, ca.SX.zeros(3)))
    return T, ca.horzcat(*columns)


def newton_euler(robot, q):
    """``rnea(dq, ddq, gravity)``: joint torques by the recursive Newton–Euler algorithm at ``q``.

    Link frames: ``R_i`` rotates frame i into frame i-1.  Joint i turns about ``a_i`` (frame-i
    axes: ``R_i^T z`` in standard DH, ``z`` in modified DH) through a point ``P_i`` on the axis;
    ``r_i`` is ``o_i − P_i`` in frame i (standard: ``P_i`` is ``o_{i-1}``) and ``s_i`` is
    ``P_i − o_{i-1}`` in frame i-1 (modified: ``P_i`` is ``o_i``).  ``gravity`` is the gravity
    vector in the world frame (``None``: no gravity); it enters as the base acceleration.
    Forces and moments on link i are about ``o_i``; the torque is the moment about ``P_i``.
    """
    import casadi as ca

    convention, rows, base, _, _ = read_table(robot)
    if not all(r.revolute and r.inertia is not None for r in rows):
        raise PeerError("the CasADi peer's dynamics need revolute joints with inertial data")
    z = ca.DM([0, 0, 1])
    frames = []  # (R, axis, r, s, o_i - o_{i-1} in frame i-1)
    for i, row in enumerate(rows):
        A = joint_transform(convention, row, q[i])
        R, offset = A[:3, :3], A[:3, 3]
        if convention == "standard":
            frames.append((R, R.T @ z, R.T @ offset, ca.DM.zeros(3), offset))
        else:
            frames.append((R, z, ca.DM.zeros(3), offset, offset))
    n_joints = len(rows)

    def rnea(dq, ddq, gravity):
        g0 = np.zeros(3) if gravity is None else base[:3, :3].T @ np.asarray(gravity)
        w, dw, dv = ca.DM.zeros(3), ca.DM.zeros(3), -ca.DM(g0)
        motion = []
        for i, (R, axis, r, s, _) in enumerate(frames):
            dv = dv + ca.cross(dw, s) + ca.cross(w, ca.cross(w, s))  # acceleration of P_i
            w_in = R.T @ w
            w = w_in + dq[i] * axis
            dw = R.T @ dw + ddq[i] * axis + dq[i] * ca.cross(w_in, axis)
            dv = R.T @ dv + ca.cross(dw, r) + ca.cross(w, ca.cross(w, r))  # of o_i
            c = ca.DM(rows[i].com)
            motion.append((w, dw, dv + ca.cross(dw, c) + ca.cross(w, ca.cross(w, c))))
        f, n, torques = ca.DM.zeros(3), ca.DM.zeros(3), [None] * n_joints
        for i in reversed(range(n_joints)):
            row, (w, dw, ac), (_, axis, r, _, _) = rows[i], motion[i], frames[i]
            if i + 1 < n_joints:  # the child's force and moment, moved to o_i
                R1, offset1 = frames[i + 1][0], frames[i + 1][4]
                f = R1 @ f
                n = R1 @ n + ca.cross(offset1, f)
            inertia, c = ca.DM(row.inertia), ca.DM(row.com)
            f = f + row.mass * ac
            n = n + ca.cross(c, row.mass * ac) + inertia @ dw + ca.cross(w, inertia @ w)
            torques[i] = ca.dot(axis, n + ca.cross(r, f)) + row.rotor * ddq[i]
        return ca.vertcat(*torques)

    return rnea


def functions(robot, kernels=tuple(NAMES), prefix: str | None = None) -> list:
    """The peer's ``casadi.Function`` objects, named ``<prefix>_<kernel>`` (prefix: the robot's
    name) with the inputs and outputs of symkin's generated CasADi module."""
    import casadi as ca

    n = robot.dof
    q, dq, x = (ca.SX.sym(name, n) for name in ("q", "dq", "x"))
    p = ca.SX.sym("p", len(robot.parameters))
    prefix = prefix or robot.name
    built = []
    for kernel in kernels:
        if kernel in ("fk", "fk_jacobian"):
            T, J = kinematics(robot, q)
            inputs, outputs = [q, p], [T] if kernel == "fk" else [T, J]
        else:
            rnea = newton_euler(robot, q)
            gravity = read_table(robot)[4]
            inputs = [q, dq, x, p]
            if kernel == "inverse_dynamics":
                outputs = [rnea(dq, x, gravity)]
            else:
                zero = ca.DM.zeros(n)
                bias = rnea(dq, zero, gravity)
                unit = ca.DM.eye(n)
                mass = ca.horzcat(*(rnea(zero, unit[:, j], None) for j in range(n)))
                outputs = [ca.solve(mass, x - bias)]
        names_in, names_out = NAMES[kernel]
        built.append(ca.Function(f"{prefix}_{kernel}", inputs, outputs, names_in, names_out))
    return built


def newton_euler_forward_dynamics(robot, inverse: bool = False):
    """``ddq = FD(q, dq, tau, p)`` (``p`` unused), or with ``inverse`` ``tau = ID(q, dq, ddq,
    p)``, as one ``casadi.Function``: the peer's dynamics, for the trajectory benchmarks."""
    kernel = "inverse_dynamics" if inverse else "forward_dynamics"
    return functions(robot, (kernel,), prefix="peer")[0]
