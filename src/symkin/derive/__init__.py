"""Symbolic derivations: a :class:`Robot` in, an immutable :class:`Model` out.

Nothing here reads files, prints or imports code emitters.  Each quantity is derived on first
use and cached on the model; :func:`derive` caches models per robot.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import cached_property, lru_cache
from typing import Any, TypeVar

import sympy as sp

from symkin.derive import jacobians
from symkin.derive.budget import (
    DEFAULT_BUDGET_SECONDS,
    NOT_SQUARE,
    ClosedForm,
    closed_form_within,
    not_attempted,
)
from symkin.derive.derivatives import TorqueDerivatives, torque_derivatives
from symkin.derive.determinant import (
    factored_determinant,
    factored_gram_determinant,
    too_large_to_factor,
)
from symkin.derive.display import rich_display
from symkin.derive.dynamics import Dynamics
from symkin.derive.elastic import MotorSide, motor_side_dynamics
from symkin.derive.energy import Energies, energies_from_dynamics
from symkin.derive.kinematics import Kinematics, euler_zyx_of_tool, kinematics_from_robot
from symkin.derive.lagrange import lagrange_dynamics
from symkin.derive.motion import PointMotion
from symkin.derive.named_pose import NamedPose, named_pose
from symkin.derive.newton_euler import inverse_dynamics_recursion, newton_euler_dynamics
from symkin.derive.readable import Readable, readable_form
from symkin.derive.wrench import tip_load, wrench_torque
from symkin.errors import ParameterError, SymkinError
from symkin.progress import phase
from symkin.robot import Robot
from symkin.symbols import joint_symbols, wrench_symbols

__all__ = [
    "ClosedForm",
    "DerivationError",
    "Dynamics",
    "Energies",
    "Model",
    "PointMotion",
    "derive",
]

Method = TypeVar("Method", bound=Callable[..., Any])


class DerivationError(SymkinError):
    """A derivation step failed inside SymPy/SymEngine; the message names the robot and the
    quantity instead of a traceback from deep inside the algebra."""


def derivation_step(quantity: str) -> Callable[[Method], Method]:
    """Turn any exception of the algebra inside ``quantity``'s derivation into one
    :class:`DerivationError` (the loader rejects the constructs known to cause them; this is
    the net for the rest).  The step is a progress phase named ``quantity``."""

    def decorate(method: Method) -> Method:
        @functools.wraps(method)
        def derive_quantity(self: Model, *args: Any, **kwargs: Any) -> Any:
            try:
                with phase(quantity if self.simplified else f"{quantity} (product form)"):
                    return method(self, *args, **kwargs)
            except SymkinError:
                raise
            except (ArithmeticError, TypeError, ValueError, KeyError, RecursionError) as error:
                raise DerivationError(
                    f"{self.robot.name}: cannot derive {quantity}: {type(error).__name__}: "
                    f"{str(error)[:200]} (an expression of the robot file symkin cannot handle; "
                    "if the file is valid, please report it)"
                ) from error

        return derive_quantity  # type: ignore[return-value]

    return decorate


@dataclass(frozen=True)
class Model:
    """Closed-form kinematics of one robot (SymPy expressions in ``q1..qn`` and parameters).

    Velocities use ``dq1..dqn`` and accelerations ``ddq1..ddqn``.  With ``simplified=False``
    every quantity keeps its raw product form: the input of code generation.
    """

    robot: Robot
    simplified: bool = True
    # Seconds per optional closed form (determinant, singular set, inverse, manipulability);
    # None: no limit.  closed_forms=False skips them (generated code computes numerically).
    budget: float | None = DEFAULT_BUDGET_SECONDS
    closed_forms: bool = True

    def __post_init__(self) -> None:
        if self.budget is not None and not 0 < self.budget < math.inf:
            raise ParameterError(
                f"{{budget}} must be a positive number of seconds or None, got {self.budget!r}"
            )

    def _repr_png_(self) -> bytes | None:
        """Jupyter: the arm at its pose ``home`` (or q = 0), see :mod:`symkin.derive.display`."""
        return rich_display("png", self)

    def _repr_latex_(self) -> str | None:
        """Jupyter: the forward kinematics ``T`` in LaTeX, see :mod:`symkin.derive.display`."""
        return rich_display("latex", self)

    @cached_property
    @derivation_step("the link transforms and forward kinematics")
    def kinematics(self) -> Kinematics:
        """Readable (angle sums contracted) when :attr:`simplified` and the contraction fits
        the budget; else the product form (``kinematics.simplified`` is then ``False``, so
        every later quantity keeps its product form too)."""
        if not self.simplified:
            return kinematics_from_robot(self.robot, simplified=False)
        return self._readable_kinematics_and_jacobian[0]

    @cached_property
    def _readable_kinematics_and_jacobian(self) -> Readable:
        """FK and geometric Jacobian contracted within the budget, else their product form
        (see :mod:`symkin.derive.readable`)."""
        form = readable_form(self.robot, self.budget)
        if form.found:
            return form.value
        return self.product_form.kinematics, self.product_form.geometric_jacobian

    @cached_property
    def named_pose(self) -> NamedPose:
        """FK and geometric Jacobian as named intermediates, link by link (the kernels' form
        of a chain without a readable form; see :mod:`symkin.derive.named_pose`)."""
        return named_pose(self.robot)

    @cached_property
    def product_form(self) -> Model:
        """The same model unsimplified (shortest generated code after CSE)."""
        return self if not self.simplified else dataclasses.replace(self, simplified=False)

    @cached_property
    def q(self) -> tuple[sp.Symbol, ...]:
        # Not self.kinematics.q: naming the inputs must not start the readable contraction.
        return joint_symbols(self.robot.dof)

    @cached_property
    def dq(self) -> tuple[sp.Symbol, ...]:
        return joint_symbols(self.robot.dof, "dq")

    @cached_property
    def ddq(self) -> tuple[sp.Symbol, ...]:
        return joint_symbols(self.robot.dof, "ddq")

    @property
    def link_transforms(self) -> tuple[sp.ImmutableMatrix, ...]:
        """``A_1 .. A_n``: pose of frame i in frame i-1."""
        return self.kinematics.link_transforms

    @property
    def frame_transforms(self) -> tuple[sp.ImmutableMatrix, ...]:
        """``T_0_0 (= base) .. T_0_n``."""
        return self.kinematics.frame_transforms

    @property
    def forward_kinematics(self) -> sp.ImmutableMatrix:
        """``T = base A_1 ... A_n tool``."""
        return self.kinematics.forward_kinematics

    @property
    def tool_position(self) -> sp.ImmutableMatrix:
        return self.kinematics.tool_position

    @cached_property
    @derivation_step("the Z-Y-X Euler angles")
    def euler_zyx(self) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
        """``(psi, theta, phi)`` with ``R = Rz(psi) Ry(theta) Rx(phi)``."""
        return euler_zyx_of_tool(self.kinematics, "atan2")

    @cached_property
    def euler_zyx_lecture(self) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
        """The same angles by the lecture's eq. (14.7) form of ``theta``."""
        return euler_zyx_of_tool(self.kinematics, "lecture")

    @cached_property
    @derivation_step("the geometric Jacobian")
    def geometric_jacobian(self) -> sp.ImmutableMatrix:
        """6 x n, base frame, linear rows first."""
        if self.simplified:
            return self._readable_kinematics_and_jacobian[1]
        return jacobians.geometric_jacobian(self.robot, self.kinematics)

    @cached_property
    def geometric_jacobian_tool(self) -> sp.ImmutableMatrix:
        """The geometric Jacobian with both blocks expressed in the tool frame."""
        rotation = self.kinematics.tool_rotation.T
        return jacobians.rotate_jacobian(self.kinematics, self.geometric_jacobian, rotation)

    @cached_property
    def position_jacobian(self) -> sp.ImmutableMatrix:
        """Analytic ``dp/dq`` (3 x n)."""
        return jacobians.position_jacobian(self.kinematics)

    @cached_property
    def euler_zyx_jacobian(self) -> sp.ImmutableMatrix:
        """Analytic Jacobian of ``[p; psi, theta, phi]`` (6 x n)."""
        return jacobians.analytic_jacobian(self.kinematics, self.euler_zyx)

    @lru_cache(maxsize=8)  # noqa: B019 - models are few, long-lived and hashable
    @derivation_step("the analytic Jacobian")
    def analytic_jacobian(self, representation: str = "zyx") -> jacobians.AnalyticJacobian:
        """``[Jv; E(phi)^-1 Jw]`` for orientation coordinates ``phi``: ``"zyx"``, ``"rpy"``,
        ``"zyz"`` or ``"rotation_vector"``, in ``q`` and the coordinate symbols, with the
        representation's singular set (see :class:`jacobians.AnalyticJacobian`).
        :attr:`euler_zyx_jacobian` is the Z-Y-X one differentiated directly, in ``q`` alone."""
        return jacobians.analytic_jacobian_of(
            self.robot, self.kinematics, self.geometric_jacobian, representation
        )

    @cached_property
    def geometric_jacobian_derivative(self) -> sp.ImmutableMatrix:
        """``dJ/dt`` of the geometric Jacobian, in ``q`` and ``dq``."""
        return jacobians.jacobian_derivative(self.kinematics, self.geometric_jacobian, self.dq)

    @cached_property
    def task_rows(self) -> tuple[str, ...]:
        """Default rows of the task Jacobian (see :func:`jacobians.default_task_rows`).

        Read off the product form: its identically zero rows are zero entry by entry (a zero
        axis or offset component multiplies through), so no contraction is derived for it,
        and a 6-joint arm needs no Jacobian at all."""
        if self.robot.dof == len(jacobians.ROW_NAMES):
            return jacobians.ROW_NAMES
        return jacobians.default_task_rows(self.product_form.geometric_jacobian)

    def task_jacobian(self, rows: Sequence[str] | None = None) -> sp.ImmutableMatrix:
        """The chosen rows (names ``x y z wx wy wz``) of the geometric Jacobian."""
        return jacobians.task_jacobian(self.geometric_jacobian, rows or self.task_rows)

    def determinant_form(self, rows: Sequence[str] | None = None) -> ClosedForm:
        """The factored determinant of the task Jacobian as a :class:`ClosedForm`: found,
        ``"not square"``, ``"over budget"`` or ``"not attempted"``."""
        return self._determinant_form(tuple(rows or self.task_rows))

    @lru_cache(maxsize=8)  # noqa: B019 - models are few, long-lived and hashable
    @derivation_step("the Jacobian determinant")
    def _determinant_form(self, rows: tuple[str, ...]) -> ClosedForm:
        jacobians.rows_from_names(rows)
        quantity = "factored determinant"
        if len(rows) != self.robot.dof:
            return ClosedForm(quantity, NOT_SQUARE, None, "the task Jacobian is not square")
        if not self.closed_forms:
            return not_attempted(quantity, self.robot.name)
        matrix = jacobians.determinant_matrix(
            self.robot, self.kinematics, self.geometric_jacobian, rows
        )
        if rows == jacobians.ROW_NAMES:  # the middle-frame matrix, where the measure is calibrated
            hopeless = too_large_to_factor(quantity, self.robot.name, matrix)
            if hopeless:
                return hopeless
        return self._within(quantity, lambda: factored_determinant(matrix, self.q))

    def _within(self, quantity: str, compute: Callable[[], Any]) -> ClosedForm:
        return closed_form_within(quantity, self.robot.name, self.budget, compute)

    def determinant(self, rows: Sequence[str] | None = None) -> sp.Expr | None:
        """Factored determinant of the task Jacobian; ``None`` when it is not square or has
        no closed form within the budget (:meth:`determinant_form` says which)."""
        return self.determinant_form(rows).value

    def singular_form(self, rows: Sequence[str] | None = None) -> ClosedForm:
        """:meth:`singular_configurations` as a :class:`ClosedForm` (value: the conditions)."""
        return self._singular_form(tuple(rows or self.task_rows))

    @lru_cache(maxsize=8)  # noqa: B019 - models are few, long-lived and hashable
    @derivation_step("the singular configurations")
    def _singular_form(self, rows: tuple[str, ...]) -> ClosedForm:
        determinant = self.determinant_form(rows)
        if not determinant.found:
            return dataclasses.replace(determinant, quantity="singular configurations")
        return self._within(
            "singular configurations",
            lambda: jacobians.singular_configurations(determinant.value, self.q),
        )

    def singular_configurations(self, rows: Sequence[str] | None = None) -> tuple[sp.Eq, ...]:
        """Where the task Jacobian's determinant vanishes (empty when it is not square or
        the closed form is not available: see :meth:`singular_form`)."""
        return self.singular_form(rows).value or ()

    @lru_cache(maxsize=8)  # noqa: B019 - models are few, long-lived and hashable
    @derivation_step("the adjugate inverse")
    def inverse_form(self, rows: tuple[str, ...] | None = None) -> ClosedForm:
        """:meth:`inverse_task_jacobian` as a :class:`ClosedForm`."""
        determinant = self.determinant_form(rows)
        if not determinant.found:
            return dataclasses.replace(determinant, quantity="adjugate inverse")
        matrix = self.task_jacobian(rows)
        return self._within(
            "adjugate inverse",
            lambda: jacobians.inverse_from_adjugate(self.kinematics, matrix, determinant.value),
        )

    def inverse_task_jacobian(self, rows: Sequence[str] | None = None) -> sp.ImmutableMatrix:
        """``adj(J) / det(J)`` of the square task Jacobian."""
        inverse = self.inverse_form(tuple(rows) if rows else None)
        if inverse.status == NOT_SQUARE:
            raise ValueError("the task Jacobian is not square; choose n rows")
        if not inverse.found:
            raise SymkinError(inverse.note)
        return inverse.value

    @lru_cache(maxsize=8)  # noqa: B019 - models are few, long-lived and hashable
    @derivation_step("the manipulability")
    def manipulability_form(self, rows: tuple[str, ...] | None = None) -> ClosedForm:
        """:meth:`manipulability` as a :class:`ClosedForm`."""
        rows = rows or self.task_rows
        determinant = self.determinant_form(rows)
        quantity = "symbolic manipulability"
        if determinant.status != NOT_SQUARE:
            value = sp.Abs(determinant.value) if determinant.found else None
            return dataclasses.replace(determinant, quantity=quantity, value=value)
        if not self.closed_forms:
            return not_attempted(quantity, self.robot.name)
        matrix = jacobians.determinant_matrix(
            self.robot, self.kinematics, self.geometric_jacobian, rows
        )
        return self._within(quantity, lambda: sp.sqrt(factored_gram_determinant(matrix, self.q)))

    def manipulability(self, rows: Sequence[str] | None = None) -> sp.Expr | None:
        """Yoshikawa's ``sqrt(det(J J^T))`` of the task Jacobian (``|det J|`` when square);
        ``None`` without a closed form within the budget (see :meth:`manipulability_form`)."""
        return self.manipulability_form(tuple(rows) if rows else None).value

    @cached_property
    @derivation_step("Lagrange's equations of motion")
    def lagrange(self) -> Dynamics:
        """Equations of motion by Lagrange (readable; for small robots)."""
        return lagrange_dynamics(self.robot, self.kinematics, self.dq, self.ddq)

    @cached_property
    @derivation_step("the Newton-Euler equations of motion")
    def newton_euler(self) -> Dynamics:
        """Equations of motion by recursive Newton–Euler (named intermediates; any size)."""
        return newton_euler_dynamics(self.robot, self._link_kinematics, self.dq, self.ddq)

    @cached_property
    @derivation_step("the Newton-Euler recursion")
    def inverse_dynamics_recursion(
        self,
    ) -> tuple[tuple[tuple[sp.Symbol, sp.Expr], ...], sp.ImmutableMatrix]:
        """Named intermediates and ``tau(q, dq, ddq)`` of one Newton–Euler pass."""
        return inverse_dynamics_recursion(self.robot, self._link_kinematics, self.dq, self.ddq)

    @property
    def _link_kinematics(self) -> Kinematics:
        """The kinematics the recursions read: only the link transforms (and the base), which
        are the same in both forms, so the product form's (built in milliseconds), and
        dynamics alone never waits for the readable contraction of a long chain."""
        return self.product_form.kinematics

    @cached_property
    @derivation_step("the elastic joints' motor-side inverse dynamics")
    def motor_side(self) -> MotorSide:
        """``theta`` and ``tau_m`` of a robot with elastic joints (:mod:`.elastic`)."""
        return motor_side_dynamics(
            self.robot, self.inverse_dynamics_recursion, self.q, self.dq, self.ddq
        )

    @cached_property
    @derivation_step("the inverse dynamics' derivatives")
    def inverse_dynamics_derivatives(self) -> TorqueDerivatives:
        """``tau``, ``dtau/dq`` and ``dtau/ddq`` through the Newton–Euler recursion's named
        intermediates (:mod:`symkin.derive.derivatives`)."""
        assignments, torque = self.inverse_dynamics_recursion
        return torque_derivatives(assignments, torque, self.q, self.dq)

    @cached_property
    def wrench(self) -> tuple[sp.Symbol, ...]:
        """``w = (f, n)`` on the tool, base frame, at the tool point (``w_fx .. w_nz``)."""
        return wrench_symbols()

    @cached_property
    @derivation_step("the torques of an external wrench")
    def wrench_torque(self) -> sp.ImmutableMatrix:
        """``-J^T w`` (docs/conventions.md, External wrench): add it to ``tau``."""
        return wrench_torque(self.geometric_jacobian, self.wrench)

    @cached_property
    @derivation_step("the Newton-Euler recursion with an external wrench")
    def inverse_dynamics_wrench_recursion(
        self,
    ) -> tuple[tuple[tuple[sp.Symbol, sp.Expr], ...], sp.ImmutableMatrix]:
        """``tau = M ddq + C dq + G + F - J^T w`` in one Newton–Euler pass, ``-w`` as the
        outer boundary force (:func:`symkin.derive.wrench.tip_load`)."""
        tip = tip_load(self.robot, self.kinematics, self.wrench)
        return inverse_dynamics_recursion(self.robot, self.kinematics, self.dq, self.ddq, tip)

    @cached_property
    @derivation_step("the static torques")
    def static_torque_recursion(
        self,
    ) -> tuple[tuple[tuple[sp.Symbol, sp.Expr], ...], sp.ImmutableMatrix]:
        """``G - J^T w``: the torques that hold the arm at rest against gravity and ``w``
        (one Newton–Euler pass at ``dq = ddq = 0``).  Without a readable form the wrench is
        turned into frame n by the named frames of :attr:`named_pose` (the product form's
        nested ``R_0_n`` cost a generic 12R's kernel 10 s of CSE)."""
        zeros = [sp.Integer(0)] * self.robot.dof
        if self.kinematics.simplified:
            tip = tip_load(self.robot, self.kinematics, self.wrench)
            return inverse_dynamics_recursion(self.robot, self.kinematics, zeros, zeros, tip)
        pose = self.named_pose
        named = dataclasses.replace(self.kinematics, frame_transforms=pose.frame_transforms)
        tip = tip_load(self.robot, named, self.wrench)
        recursion = inverse_dynamics_recursion(self.robot, self.kinematics, zeros, zeros, tip)
        return pose.assignments + tuple(recursion[0]), recursion[1]

    @cached_property
    @derivation_step("the energies")
    def energies(self) -> Energies:
        """Kinetic and potential energy and the Lagrangian (:mod:`symkin.derive.energy`); the
        kinetic energy is written in the Newton–Euler mass matrix's intermediates."""
        return energies_from_dynamics(self.robot, self.kinematics, self.newton_euler)

    @derivation_step("the point kinematics")
    def point_motion(self, link: int, point: Sequence[sp.Expr | float]) -> PointMotion:
        """Position, velocity and acceleration of a point fixed in ``link`` (base frame).

        Plain numbers become exact rationals of their decimal text (0.1 -> 1/10), so the
        reference evaluator and the generated kernels share one expression.
        """
        coordinates = tuple(
            c if isinstance(c, sp.Basic) else sp.nsimplify(c, rational=True) for c in point
        )
        return PointMotion(self.robot, self.kinematics, link, coordinates, self.dq, self.ddq)


@lru_cache(maxsize=32)
def derive(
    robot: Robot, budget: float | None = DEFAULT_BUDGET_SECONDS, closed_forms: bool = True
) -> Model:
    """The symbolic model of ``robot`` (cached: the same arguments give the same model).

    ``budget``: seconds for each optional closed form (factored determinant, singular
    configurations, adjugate inverse, symbolic manipulability; ``None``: no limit); past it
    a :class:`~symkin.errors.BudgetWarning` says so and generated code computes the
    determinant and manipulability numerically.  ``closed_forms=False`` does not attempt them.
    """
    return Model(robot, budget=budget, closed_forms=closed_forms)
