"""The spec layer: what to compute, independent of any language.

:mod:`~symkin.kernels.spec` (the validated :class:`Kernel` type and operation counts),
:mod:`~symkin.kernels.passes` (rewrites of named intermediates),
:mod:`~symkin.kernels.catalogue` (the kernels a robot gets), :mod:`~symkin.kernels.ik`
(the IK plans and settings both the Python and the C solvers read).
"""

from symkin.kernels.catalogue import (
    dynamics_inputs,
    dynamics_kernels,
    inertial_symbols,
    kinematics_kernels,
    point_kernels,
    pose_kernels,
    state_inputs,
)
from symkin.kernels.passes import kernel_from_assignments
from symkin.kernels.spec import (
    OPERATION_KINDS,
    Kernel,
    KernelInput,
    KernelOutput,
    count_operations,
    kernel_from_outputs,
)
from symkin.kernels.statics import statics_kernels

__all__ = [
    "OPERATION_KINDS",
    "Kernel",
    "KernelInput",
    "KernelOutput",
    "count_operations",
    "dynamics_inputs",
    "dynamics_kernels",
    "inertial_symbols",
    "kernel_from_assignments",
    "kernel_from_outputs",
    "kinematics_kernels",
    "point_kernels",
    "pose_kernels",
    "state_inputs",
    "statics_kernels",
]
