"""What each measured process of ``bench/derivation_scaling.py`` does (one fresh process each).

``python bench/scaling_children.py cli ARGS...`` runs ``symkin ARGS...`` (see :func:`cli`).
``python bench/scaling_children.py KIND SOURCE EXTRA`` prints one JSON object on its last line:
``{"seconds": ...}`` (CPU seconds of the timed section; imports, loading the robot and the
same-arm checks are not timed) and, for the peers, ``"checked"``, the largest difference of
their check.  KIND is ``fkj``, ``tau``, ``full`` (symkin in process), ``sb-tau``, ``sb-full``
(SymPyBotics; EXTRA is its checkout) or ``pin`` (Pinocchio's ``rnea``; EXTRA is the folder the
cold ``symkin derive`` wrote, whose NumPy module it is checked against, or "").
"""

from __future__ import annotations

import json
import math
import statistics
import sys
from pathlib import Path

from derivation_time import CLOCK, peak_rss_mb

ROOT = Path(__file__).resolve().parent.parent
RNEA_STATES = 1000  # distinct states one timing pass of Pinocchio's rnea walks through
RNEA_PASSES = 5
CHECK_TOLERANCE = 1e-8  # Pinocchio vs symkin torques, relative to the largest torque
PEER_KINDS = ("sb-tau", "sb-full")


def _load(source: str, symbolic_inertia: bool = False):
    """The robot (catalogue name or file), optionally without its link data."""
    import dataclasses
    import warnings

    import symkin
    from symkin.errors import RobotWarning

    with warnings.catch_warnings():  # the PUMA's documented triangle-inequality warning
        warnings.simplefilter("ignore", RobotWarning)
        robot = symkin.load_robot(source)
    if symbolic_inertia:
        joints = tuple(dataclasses.replace(j, link=None) for j in robot.joints)
        robot = dataclasses.replace(robot, joints=joints)
    return robot


def _child_fkj(source: str) -> dict:
    import symkin

    robot = _load(source)
    start = CLOCK()
    model = symkin.derive(robot)
    model.forward_kinematics  # noqa: B018 - cached properties: reading them derives them
    model.geometric_jacobian  # noqa: B018
    return {"seconds": CLOCK() - start}


def _child_dynamics(kind: str, source: str) -> dict:
    from dynamics_speed import _child_full, _child_tau

    robot = _load(source, symbolic_inertia=True)
    return (_child_tau if kind == "tau" else _child_full)(robot)


def _sympybotics_definition(source: str):
    """SymPyBotics' ``RobotDef`` of the robot's DH table (alpha, a, d, theta per joint)."""
    import sympy
    import sympybotics

    robot = _load(source)
    rows = []
    for joint in robot.joints:
        if joint.type != "revolute":
            raise SystemExit(f"{source}: SymPyBotics rows here are revolute only")
        angle = "-q" if getattr(joint, "flip", False) else "q"
        rows.append((str(joint.alpha), str(joint.a), str(joint.d), f"{angle} + ({joint.theta})"))
    definition = sympybotics.RobotDef(robot.name, rows, dh_convention=robot.convention)
    definition.frictionmodel = None
    definition.gravityacc = sympy.Matrix([float(g) for g in robot.gravity])
    return definition


def _child_sympybotics(kind: str, source: str, directory: str) -> dict:
    sys.path.insert(0, directory)
    import sympybotics
    from sympybotics.symcode import Subexprs

    definition = _sympybotics_definition(source)
    to_c = sympybotics.robot_code_to_func
    start = CLOCK()
    if kind == "sb-tau":  # what RobotDynCode does for tau, alone
        geometry = sympybotics.Geometry(definition)
        dynamics = sympybotics.Dynamics(definition, geometry)
        collector = Subexprs()
        dynamics.gen_invdyn(collector.collect)
        to_c("C", collector.get(dynamics.invdyn), "tau_out", "tau", definition)
    else:
        model = sympybotics.RobotDynCode(definition)
        geometry = model.geo
        for name in ("invdyn", "g", "c", "C", "M", "H"):
            to_c("C", getattr(model, f"{name}_code"), f"{name}_out", name, definition)
    seconds = CLOCK() - start
    checked = _sympybotics_pose_error(source, definition, geometry)
    return {"seconds": seconds, "checked": checked, "rss_mb": peak_rss_mb()}


def _sympybotics_pose_error(source: str, definition, geometry) -> float:
    """Largest difference of SymPyBotics' last-link pose and the numeric DH product of the
    robot's table (``tests/numeric_dh.py``) at three random configurations: the same arm?"""
    import numpy as np
    import sympy

    sys.path.insert(0, str(ROOT / "tests"))
    from numeric_dh import modified_dh, standard_dh

    robot = _load(source)
    values = {s: robot.parameter_values()[s.name] for s in robot.parameter_symbols}
    link = modified_dh if robot.convention == "modified" else standard_dh
    rng, worst = np.random.default_rng(17), 0.0
    for _ in range(3):
        q = rng.uniform(-math.pi, math.pi, robot.dof)
        pose = np.eye(4)
        for joint, angle in zip(robot.joints, q, strict=True):
            d, a, alpha, theta = (float(sympy.sympify(v).subs(values)) for v in
                                  (joint.d, joint.a, joint.alpha, joint.theta))  # fmt: skip
            pose = pose @ link(theta + (-angle if getattr(joint, "flip", False) else angle),
                               d, a, alpha)  # fmt: skip
        theirs = geometry.T[-1].subs(dict(zip(definition.q, q, strict=True)))
        # SymPyBotics makes its own symbols from the names: substitute by name.
        by_name = {s.name: v for s, v in values.items()}
        theirs = theirs.subs({s: by_name[s.name] for s in theirs.free_symbols}).evalf()
        worst = max(worst, float(np.abs(np.array(theirs, dtype=float) - pose).max()))
    return worst


def _generated_inverse_dynamics(out: Path, name: str):
    from codegen_speed import load_module

    return load_module(out / "numpy" / f"{name}_kinematics.py").inverse_dynamics


def _child_pinocchio(source: str, out: str) -> dict:
    import numpy as np

    sys.path.insert(0, str(ROOT / "tests"))
    from test_dynamics_oracles import pinocchio_model

    robot = _load(source)
    if any(j.link is None for j in robot.joints):
        return {"error": "no inertial data"}
    pin, model = pinocchio_model(robot)
    data = model.createData()
    rng = np.random.default_rng(15)
    n = robot.dof
    q, dq, ddq = (rng.uniform(-r, r, (RNEA_STATES, n)) for r in (math.pi, 2.0, 5.0))
    rotor = np.array([float(j.link.motor_inertia or 0) for j in robot.joints])
    worst = None
    if out and (Path(out) / "numpy").is_dir():  # the same arm as symkin's? (before timing)
        ours = _generated_inverse_dynamics(Path(out), robot.name)
        worst = 0.0
        for i in range(10):
            theirs = pin.rnea(model, data, q[i], dq[i], ddq[i]) + rotor * ddq[i]
            mine = np.asarray(ours(q[i], dq[i], ddq[i]), dtype=float).ravel()
            scale = max(1.0, float(np.abs(theirs).max()))
            worst = max(worst, float(np.abs(mine - theirs).max()) / scale)
        if worst > CHECK_TOLERANCE:
            return {"error": f"disagrees with symkin's tau by {worst:.1e} (relative)"}
    rnea, passes = pin.rnea, []
    for _ in range(RNEA_PASSES):
        start = CLOCK()
        for i in range(RNEA_STATES):
            rnea(model, data, q[i], dq[i], ddq[i])
        passes.append((CLOCK() - start) / RNEA_STATES)
    return {"seconds": statistics.median(passes), "checked": worst}


RUSAGE_TAG = "scaling-rusage "  # the last stderr line of a ``cli`` child


def cli(argv: list[str]) -> None:
    """Run the ``symkin`` command with ``argv`` exactly as its console script does, and at exit
    write the CPU seconds and peak RSS (MB) of symkin's own process and of the processes it
    waited for (the C compiler) as one JSON line on stderr: ``os.wait4`` in the parent sees
    only their sum and the larger peak.  symkin's own peak is ``VmHWM``
    (:func:`derivation_time.peak_rss_mb`): its ``ru_maxrss`` would include the parent's."""
    import atexit
    import resource

    def report() -> None:
        own, tools = (resource.getrusage(who) for who in
                      (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN))  # fmt: skip
        figures = {
            "own_cpu": own.ru_utime + own.ru_stime,
            "own_rss_mb": peak_rss_mb(),
            "compiler_cpu": tools.ru_utime + tools.ru_stime,
            "compiler_rss_mb": tools.ru_maxrss / 1024,
        }
        sys.stderr.write("\n" + RUSAGE_TAG + json.dumps(figures) + "\n")

    atexit.register(report)
    from symkin.cli import main

    sys.argv = ["symkin", *argv]
    sys.exit(main())


def child(argv: list[str]) -> None:
    if argv[0] == "cli":
        cli(argv[1:])
    kind, source, extra = argv[0], argv[1], argv[2]
    if kind == "fkj":
        result = _child_fkj(source)
    elif kind in ("tau", "full"):
        result = _child_dynamics(kind, source)
    elif kind in PEER_KINDS:
        result = _child_sympybotics(kind, source, extra)
    elif kind == "pin":
        result = _child_pinocchio(source, extra)
    else:
        raise SystemExit(f"unknown child kind {kind!r}")
    print(json.dumps(result))


if __name__ == "__main__":
    child(sys.argv[1:])
