"""Size of the generated inverse dynamics and mass matrix with symbolic inertia, by how the
inertial data enter, against SymPyBotics when a checkout is given.

The issue compared symkin's ``tau`` and ``M`` with SymPyBotics' (tau 962 operations for the
PUMA 560, M 883 against 780; numeric geometry and symbolic inertia).  This script counts, for
both robots with numeric geometry, the operations of one ``tau`` kernel and one ``M`` kernel
(the same recursion and the same kernel passes as ``symkin.kernels.dynamics_kernels``; M by the
composite-rigid-body algorithm, ``symkin.derive.newton_euler.mass_matrix``) with the inertial
data as input in three forms:

* **file form**: per link the mass, the centre of mass and the inertia about it (the robot
  file's keys, the ``pi`` input of symkin's generated code);
* **barycentric**: per link the inertia about the frame origin, the first moment ``m c`` and
  the mass (SymPyBotics' and Khalil's "standard" parameters), ten per link: the kernels
  ``mass_matrix_barycentric`` and ``inverse_dynamics_barycentric`` that ``symkin derive
  --regressor`` emits (``symkin.kernels.regressor.barycentric_kernels``), counted as emitted
  (their M by the composite-rigid-body algorithm, ``symkin.derive.regressor_mass``);
* **base parameters**: the fewest combinations of those that give the same torques
  (``symkin.derive.base_parameters.symbolic_base_parameters``), the form the identification
  literature uses.

SymPyBotics is not on PyPI: with ``--sympybotics DIR`` (a checkout; never copied here) it is
run in this process on the same DH table (its ``gen_invdyn`` and ``gen_inertiamatrix`` with
its incremental CSE, ``Subexprs``, no friction, no drive inertia) and its output is counted
with symkin's counter; without it its column says "not run".  Operation counts are
deterministic, so this runs once (about ten seconds, a minute with SymPyBotics).  It prints a
Markdown table and writes it into ``docs/benchmarks.md`` between
``<!-- inertial-parameters:begin -->`` and ``<!-- inertial-parameters:end -->``.

Usage::

    .venv/bin/python bench/inertial_parameters.py
    .venv/bin/python bench/inertial_parameters.py --sympybotics /somewhere/SymPyBotics
    .venv/bin/python bench/inertial_parameters.py --no-write
"""

from __future__ import annotations

import argparse
import datetime
import sys
from pathlib import Path

import sympy as sp

from codegen_speed import write_docs
from derivation_scaling import sympybotics_version
from derivation_time import version
from dynamics_speed import DOCS, robot_variant
from symkin import derive
from symkin.derive.base_parameters import symbolic_base_parameters
from symkin.derive.newton_euler import mass_matrix
from symkin.derive.recursion import Recorder, joint_torques
from symkin.kernels import (
    KernelInput,
    count_operations,
    inertial_symbols,
    kernel_from_assignments,
    state_inputs,
)
from symkin.kernels.regressor import barycentric_kernels

BEGIN = "<!-- inertial-parameters:begin -->"
END = "<!-- inertial-parameters:end -->"
FORMS = ("file form", "barycentric", "base parameters")
ROBOTS = ("puma560", "panda")


def _kernel_operations(name: str, inputs, recorder: Recorder, matrix: sp.Matrix) -> int:
    kernel = kernel_from_assignments(
        name, name, inputs, recorder.assignments, [("out", matrix, name, "matrix")]
    )
    return kernel.operation_counts["total"]


def _mass_matrix(model, links) -> tuple[Recorder, sp.Matrix]:
    """M as ``symkin.derive.newton_euler`` builds it (the composite-rigid-body algorithm on
    ``links``, or on the file's data when None, plus the rotor inertias)."""
    recorder = Recorder("s")
    return recorder, mass_matrix(model.robot, model.kinematics, links, recorder)


def operations(name: str) -> dict[str, tuple[int, int, int]]:
    """``{form: (inertial inputs, operations of tau, operations of M)}`` for one catalogue
    robot: the barycentric form as emitted, the others as :func:`_mass_matrix` builds M."""
    robot = robot_variant(name, "symbolic", "numeric")
    model = derive(robot)
    mass, tau = barycentric_kernels(model)
    delta = mass.inputs[-1].symbols
    result = {
        "barycentric": (
            len(delta),
            tau.operation_counts["total"],
            mass.operation_counts["total"],
        )
    }
    base_links, definitions = symbolic_base_parameters(robot, model.kinematics)
    forms = {
        "file form": (None, list(inertial_symbols(model))),
        "base parameters": (base_links, [s for s, _ in definitions]),
    }
    for form, (links, symbols) in forms.items():
        pi = KernelInput("pi", tuple(symbols), form)
        recorder = Recorder("s")
        torque = joint_torques(
            robot, model.kinematics, recorder, model.dq, model.ddq, robot.gravity, links
        )
        tau = _kernel_operations(
            "tau", (*state_inputs(model, "dq", "ddq"), pi), recorder, sp.Matrix(torque)
        )
        m = _kernel_operations("M", (*state_inputs(model), pi), *_mass_matrix(model, links))
        result[form] = (len(symbols), tau, m)
    return result


def sympybotics_operations(name: str, checkout: Path) -> tuple[int, int]:
    """Operations of SymPyBotics' tau and M (its incremental CSE, ``Subexprs``) for the same
    robot with numeric geometry and its own symbolic (barycentric) inertia, no friction, no
    drive inertia, counted with symkin's counter (``symkin.kernels.count_operations``)."""
    sys.path.insert(0, str(checkout))
    import sympybotics
    from sympybotics.symcode import Subexprs

    robot = robot_variant(name, "symbolic", "numeric")
    rows = []
    for joint in robot.joints:
        if joint.type != "revolute":
            raise SystemExit(f"{name}: only revolute joints are passed to SymPyBotics here")
        rows.append((str(joint.alpha), str(joint.a), str(joint.d), f"q + ({joint.theta})"))
    definition = sympybotics.RobotDef(name, rows, dh_convention=robot.convention)
    definition.frictionmodel = None
    definition.gravityacc = sp.Matrix([float(g) for g in robot.gravity])
    geometry = sympybotics.Geometry(definition)
    dynamics = sympybotics.Dynamics(definition, geometry)
    counts = []
    for generate, attribute in ((dynamics.gen_invdyn, "invdyn"), (dynamics.gen_inertiamatrix, "M")):
        collector = Subexprs()
        generate(collector.collect)
        subexpressions, outputs = collector.get(getattr(dynamics, attribute))
        expressions = [e for _, e in subexpressions] + list(sp.Matrix(outputs))
        counts.append(count_operations(expressions)["total"])
    return counts[0], counts[1]


def render(counts: dict[str, dict[str, tuple[int, int, int]]], theirs: dict, checkout) -> str:
    today = datetime.datetime.now(datetime.UTC).date().isoformat()
    peer = (
        f"SymPyBotics ({sympybotics_version(checkout)}) was run in the same process on the same "
        "DH table: its tau and M with its incremental CSE, counted with the same counter"
        if checkout is not None
        else "SymPyBotics was not run (it is not on PyPI: pass a checkout with `--sympybotics DIR`)"
    )
    lines = [
        f"Counted on {today} with symkin {version('symkin')}, SymPy {version('sympy')}. "
        "Generated by `bench/inertial_parameters.py`. Numeric geometry, symbolic inertia; "
        "operations after the kernel passes, as in the generated files' headers, inverse "
        "dynamics tau / mass matrix M. The file form is what `symkin derive` generates; the "
        "barycentric column is the kernels `inverse_dynamics_barycentric` and "
        "`mass_matrix_barycentric` that `symkin derive --regressor` also emits, counted as "
        "emitted; every column's M by the composite-rigid-body algorithm, as the generated "
        "`mass_matrix`; the base-parameter "
        "column is the same recursion with other inputs, counted but not emitted. "
        f"{peer}; it takes barycentric parameters and has no rotor inertia.",
        "",
        "| robot | inertial inputs | file form (m, c, I about the COM) | barycentric "
        "(I about the origin, m c, m): emitted (with --regressor) | base parameters "
        "(not emitted) | SymPyBotics (barycentric) |",
        "| --- | --- | ---: | ---: | ---: | ---: |",
    ]
    for name, forms in counts.items():
        inputs = " / ".join(str(forms[f][0]) for f in FORMS)
        cells = " | ".join(f"{forms[f][1]} / {forms[f][2]}" for f in FORMS)
        peer_cell = " / ".join(map(str, theirs[name])) if name in theirs else "not run"
        lines.append(f"| {name} | {inputs} | {cells} | {peer_cell} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sympybotics", type=Path, metavar="DIR", help="SymPyBotics checkout")
    parser.add_argument("--docs", type=Path, default=DOCS, help=f"file to update ({DOCS})")
    parser.add_argument("--no-write", action="store_true", help="print only")
    args = parser.parse_args(argv)
    if args.sympybotics is not None and not (args.sympybotics / "sympybotics").is_dir():
        parser.error(f"--sympybotics {args.sympybotics}: no sympybotics package in it")
    counts = {name: operations(name) for name in ROBOTS}
    theirs = {}
    if args.sympybotics is not None:
        theirs = {name: sympybotics_operations(name, args.sympybotics) for name in ROBOTS}
    table = render(counts, theirs, args.sympybotics)
    print(table)
    if not args.no_write:
        write_docs(table, args.docs, (BEGIN, END), "Inverse dynamics by inertial parameters")
        print(f"wrote {args.docs}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
