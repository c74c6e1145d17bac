"""The robot description: frozen dataclasses, no derivation.

A :class:`Robot` is a Denavit–Hartenberg table plus what surrounds it (parameters, base and
tool transforms, gravity, joint limits, optional inertial data).  Every DH entry is a SymPy
expression in SI units and **radians**; angle units of a robot file are converted on load
(``symkin.io.robot_file``).  Change a robot with :func:`dataclasses.replace`, never by mutation.

Conventions (docs/conventions.md):

* standard (distal) DH:  ``A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``
* modified DH (Craig):   ``A_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i) Tz(d_i)``, where the
  joint row holds the ``alpha``/``a`` that precede it.
* placement (URDF-like):  ``A_i = P_i Rz(theta_i) Tz(d_i)``, where ``P_i`` is the joint's
  constant ``placement`` (pose of the joint frame i in frame i-1 at ``q_i = 0``, any rotation
  and translation); ``a`` and ``alpha`` are 0.  It is modified DH with a general constant
  part: the loaders (``symkin.io.placement``) turn each URDF-style ``origin`` + ``axis`` into
  a placement whose z axis is the joint axis.
* revolute joint:  ``theta_i = q_i + theta`` (``theta`` is the offset), ``d`` constant;
  prismatic joint: ``d_i = q_i + d`` (``d`` is the offset), ``theta`` constant.
  A flipped joint (``flip=True``) has ``-q_i`` in place of ``q_i``: it turns about (or
  slides along) the ``-z`` axis of its frame as ``q_i`` grows.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, field, fields, replace
from typing import Literal

import sympy as sp

from symkin.errors import ParameterError, RobotError
from symkin.symbols import parameter_symbol
from symkin.text import unprintable_characters

JointType = Literal["revolute", "prismatic"]
Convention = Literal["standard", "modified", "placement"]
CONVENTIONS: tuple[str, ...] = ("standard", "modified", "placement")

NAME_PATTERN = re.compile(r"^[a-z][a-z0-9_]*$")
# A robot's name starts file names (<name>_ik_closed.h, a staging folder's name) and C
# symbols; file systems allow 255 bytes per name, so keep it well short of that.
MAX_NAME_LENGTH = 64
DEFAULT_GRAVITY: tuple[sp.Expr, sp.Expr, sp.Expr] = (
    sp.Integer(0),
    sp.Integer(0),
    sp.Float("-9.81"),
)
IDENTITY = sp.ImmutableMatrix(sp.eye(4))
ZERO = sp.Integer(0)
ONE = sp.Integer(1)


@dataclass(frozen=True)
class Drive:
    """The drive of a joint: gear ratio ``G`` (motor angle = ``G`` x joint angle), rotor
    inertia ``Jm`` (motor side, kg m^2) and an optional DC motor: torque constant ``k_t``
    (N m/A), back-emf constant ``k_e`` (V s/rad), armature resistance ``R`` (ohm) and
    inductance ``L`` (H; None: the current follows the voltage at once).

    The joint torque of the DC motor is ``G k_t i`` with ``L di/dt = u - R i - k_e G dq``
    (``dq`` the joint speed, or the motor-side ``dtheta`` of an elastic joint).
    """

    gear_ratio: sp.Expr = ONE
    rotor_inertia: sp.Expr | None = None
    torque_constant: sp.Expr | None = None
    back_emf_constant: sp.Expr | None = None
    resistance: sp.Expr | None = None
    inductance: sp.Expr | None = None

    @property
    def has_motor(self) -> bool:
        """True when the DC-motor constants are given (voltage is then the input)."""
        return self.torque_constant is not None


@dataclass(frozen=True)
class Link:
    """Inertial data of the link moved by a joint (link i, in frame-i axes).

    ``inertia`` holds the tensor elements ``(ixx, iyy, izz, ixy, ixz, iyz)`` about the centre
    of mass (URDF convention: ``ixy`` is the (1,2) element of the tensor, i.e. minus the
    engineering product of inertia).  Friction: ``coulomb * sign(dq) + viscous * dq``, or the
    Stribeck curve when ``stribeck_static`` and ``stribeck_velocity`` are given.  With
    ``coulomb_negative`` the Coulomb level depends on the direction: ``coulomb`` for
    ``dq > 0`` and ``coulomb_negative`` for ``dq < 0`` (None: ``coulomb`` both ways).
    ``inertia_note``: why the tensor is as given (published lumped data that break the triangle
    inequality, say); ``symkin show`` prints it, and the loader then does not warn.

    ``coulomb_width``: the Coulomb term is smoothed for optimisers, ``sign(dq)`` replaced by
    ``tanh(dq / coulomb_width)``.  ``stiction``: the static friction level ``gamma_s`` that
    holds a joint at rest in :func:`symkin.solve.simulate.simulate` (stick/slip).

    ``stiffness``: the joint is elastic (Spong's reduced model), a spring of stiffness ``K``
    between link and motor; ``motor_inertia`` is then the motor side's inertia ``B`` and is
    not added to ``M``.  ``drive``: gear and DC motor (:class:`Drive`); a given rotor inertia
    is already reflected into ``motor_inertia`` (``G^2 Jm``) by the loader.
    """

    mass: sp.Expr
    com: tuple[sp.Expr, sp.Expr, sp.Expr]
    inertia: tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr, sp.Expr, sp.Expr]
    motor_inertia: sp.Expr = ZERO
    coulomb: sp.Expr = ZERO
    viscous: sp.Expr = ZERO
    stribeck_static: sp.Expr | None = None
    stribeck_velocity: sp.Expr | None = None
    coulomb_negative: sp.Expr | None = None
    coulomb_width: sp.Expr | None = None
    stiction: sp.Expr | None = None
    stiffness: sp.Expr | None = None
    drive: Drive | None = None
    inertia_note: str = ""

    @property
    def is_elastic(self) -> bool:
        """True for a link behind an elastic joint (``stiffness`` given)."""
        return self.stiffness is not None

    @property
    def inertia_matrix(self) -> sp.ImmutableMatrix:
        """The 3x3 inertia tensor about the centre of mass, frame-i axes."""
        ixx, iyy, izz, ixy, ixz, iyz = self.inertia
        return sp.ImmutableMatrix([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])


@dataclass(frozen=True)
class Joint:
    """One row of the DH table (SI units, radians), or one placed joint.

    ``placement``: in a robot of the ``"placement"`` convention, the constant 4x4 transform
    from frame i-1 to joint frame i at ``q_i = 0``; the joint then turns about (slides along)
    that frame's z axis: ``A_i = placement * Rz(theta_i) Tz(d_i)``.  None in a DH robot.

    ``max_velocity`` and ``max_effort``: the speed (rad/s or m/s) and torque or force (N m or N)
    limits of the joint, as URDF's ``<limit velocity effort>``; None when not given.

    ``flip``: the joint variable enters with a minus sign (``theta_i = -q_i + theta`` or
    ``d_i = -q_i + d``), as in DH tables whose joint axis points against ``z``.
    """

    type: JointType
    theta: sp.Expr = ZERO
    d: sp.Expr = ZERO
    a: sp.Expr = ZERO
    alpha: sp.Expr = ZERO
    name: str | None = None
    limits: tuple[float, float] | None = None
    link: Link | None = None
    flip: bool = False
    placement: sp.ImmutableMatrix | None = None
    max_velocity: float | None = None
    max_effort: float | None = None

    def __post_init__(self) -> None:
        if self.type not in ("revolute", "prismatic"):
            raise RobotError(f'joint \'type\' must be "revolute" or "prismatic", got {self.type!r}')
        if not isinstance(self.flip, bool):
            raise RobotError(f"joint 'flip' must be true or false, got {self.flip!r}")
        for key in ("theta", "d", "a", "alpha"):
            object.__setattr__(self, key, sp.sympify(getattr(self, key)))
        if self.placement is not None:
            object.__setattr__(self, "placement", _checked_placement(self))


def _checked_placement(joint: Joint) -> sp.ImmutableMatrix:
    """The placement as an immutable 4x4 homogeneous transform; ``a`` and ``alpha`` must be 0
    (the placement holds the whole constant part of the link transform)."""
    placement = sp.ImmutableMatrix(joint.placement)
    if placement.shape != (4, 4) or list(placement[3, :]) != [0, 0, 0, 1]:
        raise RobotError(f"joint 'placement' must be a 4x4 homogeneous transform, got {placement}")
    if joint.a != 0 or joint.alpha != 0:
        raise RobotError("a placed joint has no 'a' or 'alpha': its placement holds them")
    return placement


@dataclass(frozen=True)
class Robot:
    """A serial robot described by a DH table.

    ``parameters`` maps each named constant to its default value (``None`` when it has no
    value and stays a pure symbol).  In derivations every parameter is a SymPy symbol of that
    name; numeric evaluation substitutes the values.  ``base`` and ``tool`` are 4x4
    homogeneous transforms applied before the first and after the last joint:
    ``T = base * A_1 * ... * A_n * tool``.  ``poses`` are named configurations
    ``(name, (q1, ..., qn))`` in radians and metres (``[poses]`` in a robot file).
    """

    name: str
    joints: tuple[Joint, ...]
    convention: Convention = "standard"
    parameters: tuple[tuple[str, float | None], ...] = ()
    gravity: tuple[sp.Expr, sp.Expr, sp.Expr] = DEFAULT_GRAVITY
    base: sp.ImmutableMatrix = IDENTITY
    tool: sp.ImmutableMatrix = IDENTITY
    title: str = ""
    source: str = ""
    file: str | None = field(default=None, compare=False)
    poses: tuple[tuple[str, tuple[float, ...]], ...] = ()

    def __post_init__(self) -> None:
        if not NAME_PATTERN.match(self.name):
            raise RobotError(f"'name' must match [a-z][a-z0-9_]*, got {self.name!r}")
        if not self.joints:
            raise RobotError("a robot needs at least one joint, the joint list is empty")
        if self.convention not in CONVENTIONS:
            raise RobotError(
                f"'convention' must be one of {', '.join(CONVENTIONS)}, got {self.convention!r}"
            )
        placed = [j.placement is not None for j in self.joints]
        if any(placed) != (self.convention == "placement") or any(placed) != all(placed):
            raise RobotError(
                "every joint of a robot of the 'placement' convention has a placement, "
                "and no joint of a DH robot has one"
            )
        for key in ("title", "source"):
            # Titles reach terminals, comments of generated files and TeX: one printable line.
            bad = unprintable_characters(getattr(self, key))
            if bad:
                raise RobotError(
                    f"{key!r} must be one line of printable text; it contains {', '.join(bad)}"
                )
        object.__setattr__(self, "joints", tuple(self.joints))
        object.__setattr__(self, "parameters", tuple((n, v) for n, v in self.parameters))
        object.__setattr__(self, "gravity", tuple(sp.sympify(g) for g in self.gravity))
        object.__setattr__(self, "base", sp.ImmutableMatrix(self.base))
        object.__setattr__(self, "tool", sp.ImmutableMatrix(self.tool))
        names = [n for n, _ in self.parameters]
        if len(set(names)) != len(names):
            raise RobotError(f"duplicate parameter names in {names}")
        object.__setattr__(self, "poses", tuple((n, tuple(v)) for n, v in self.poses))
        if any(len(v) != self.dof for _, v in self.poses):
            raise RobotError(f"every pose needs {self.dof} values (one per joint)")
        joint_names = [j.name for j in self.joints if j.name is not None]
        if len(set(joint_names)) != len(joint_names):
            raise RobotError(f"duplicate joint names in {joint_names}")

    @property
    def dof(self) -> int:
        """Number of joints n."""
        return len(self.joints)

    @property
    def elastic_joints(self) -> tuple[int, ...]:
        """0-based indices of the elastic joints (a link with ``stiffness``), in order."""
        return tuple(i for i, j in enumerate(self.joints) if j.link and j.link.is_elastic)

    @property
    def parameter_symbols(self) -> tuple[sp.Symbol, ...]:
        """The parameters as real SymPy symbols, in file order."""
        return tuple(parameter_symbol(n) for n, _ in self.parameters)

    def parameter_values(self, overrides: Mapping[str, float] | None = None) -> dict[str, float]:
        """Numeric value of every parameter, ``overrides`` taking precedence.

        Raises :class:`RobotError` for an unknown name in ``overrides`` and
        :class:`ParameterError` naming the parameters that have no value.
        """
        overrides = dict(overrides or {})
        unknown = sorted(set(overrides) - {n for n, _ in self.parameters})
        if unknown:
            known = ", ".join(n for n, _ in self.parameters) or "none"
            raise RobotError(f"unknown parameter(s) {', '.join(unknown)}; this robot has: {known}")
        values = {n: overrides.get(n, v) for n, v in self.parameters}
        missing = [n for n, v in values.items() if v is None]
        if missing:
            raise ParameterError(
                f"parameter(s) {', '.join(missing)} have no value; give one with {{overrides}}"
            )
        return {n: float(v) for n, v in values.items()}  # type: ignore[arg-type]

    def with_parameter_values(self, overrides: Mapping[str, float] | None = None) -> Robot:
        """The same robot with every parameter replaced by its number: a robot without
        parameters, whose generated code has no ``p`` input and folds the constants
        (``symkin derive --numeric-parameters``)."""
        values = {parameter_symbol(n): v for n, v in self.parameter_values(overrides).items()}

        def numbers(item: object) -> object:
            if isinstance(item, sp.Basic):
                return item.xreplace(values)
            if isinstance(item, tuple):
                return tuple(numbers(x) for x in item)
            if isinstance(item, (Joint, Link, Drive)):
                return replace(
                    item, **{f.name: numbers(getattr(item, f.name)) for f in fields(item)}
                )
            return item

        return replace(
            self,
            joints=numbers(self.joints),
            parameters=(),
            gravity=numbers(self.gravity),
            base=numbers(self.base),
            tool=numbers(self.tool),
        )
