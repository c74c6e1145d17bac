"""Derivative kernels of the PUMA 560 and the Panda against Pinocchio's analytical derivatives
and CasADi's automatic ones, in one run on the same machine.

* **Robots.** The PUMA 560 is the catalogue file; Pinocchio reads symkin's URDF export of it
  (``symkin urdf``; the rotor inertias as Pinocchio's ``armature``).  The Panda is
  example-robot-data's ``panda.urdf`` read by both (symkin ``load_robot(path,
  tip="panda_hand_tcp")``; Pinocchio ``buildModelFromUrdf`` with the fingers locked, as symkin
  holds them).  Before any timing, symkin's extension and Pinocchio agree on dtau/dq, dtau/ddq,
  dddq/dq, dddq/ddq and M^-1 at random states to 1e-8 relative (the script stops otherwise).
* **Operation counts.** symkin's ``inverse_dynamics_derivatives`` kernel (tau, dtau/dq,
  dtau/ddq; the figure of the generated headers, SymPy ``count_ops`` after CSE), and the same
  kernel's CasADi function counted as CasADi counts (arithmetic instructions of the SX
  function: no inputs, outputs or constants), against CasADi's automatic derivatives
  (``casadi.jacobian`` of tau by q and by dq) of (a) symkin's own CasADi tau and (b) an
  independent recursive Newton–Euler written in CasADi in this script from the textbook
  recursion (Luh, Walker & Paul; on Pinocchio's model: joint placements, axes, inertias), and
  for the forward dynamics' derivatives, CasADi's ``jacobian`` of symkin's CasADi forward
  dynamics (a symbolic ``casadi.solve``).
* **Per call in a C loop** (``bench/derivatives_speed_loop.c``, gcc -O2, 65,536 states cycled,
  CPU time of the thread): symkin's ``<robot>_inverse_dynamics_derivatives`` and
  ``<robot>_forward_dynamics_derivatives``, and the C ``casadi.CodeGenerator`` writes for the
  AD Jacobians above; interleaved rounds, median.  Pinocchio has no C API; its C++ is timed
  from Python only (below).
* **Per call from Python**: symkin's CPython extension against Pinocchio's
  ``computeRNEADerivatives`` / ``computeABADerivatives`` (the Python bindings of its C++),
  interleaved repeats, CPU time (``codegen_speed.time_contenders``).

The script writes its table into ``docs/benchmarks.md`` between ``<!-- derivatives:begin -->``
and ``<!-- derivatives:end -->``.  No test passes or fails on it.

Usage::

    .venv/bin/python bench/derivatives_speed.py [--quick] [--no-write]
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import subprocess
import sys
import tempfile
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from codegen_speed import (
    FULL,
    QUICK,
    CheckError,
    Contender,
    Peers,
    Result,
    compile_c,
    compiler,
    compiler_version,
    load_module,
    time_contenders,
    write_docs,
)
from derivation_time import cpu_model, version

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs" / "benchmarks.md"
MARKERS = ("<!-- derivatives:begin -->", "<!-- derivatives:end -->")
HARNESS = Path(__file__).resolve().with_name("derivatives_speed_loop.c")
SAMPLES = 4096  # distinct states of the Python timings
TOLERANCE = 1e-8  # relative difference allowed between symkin and a peer before timing
FLAGS = ("-O2",)
ROBOTS = {
    "puma560": "PUMA 560 (Pinocchio: symkin's URDF export)",
    "panda": "Panda (example-robot-data URDF, both)",
}


def _progress(text: str) -> None:
    print(text, file=sys.stderr, flush=True)


# --------------------------------------------------------------------------- robots


def robot_pair(name: str):
    """``(symkin robot, Pinocchio model)`` of the same arm (see the module docstring)."""
    import pinocchio as pin

    import symkin
    from symkin.emit.urdf import urdf_text

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if name == "puma560":
            robot = symkin.load_robot("puma560")
            model = pin.buildModelFromXML(urdf_text(robot, "derivatives bench"))
            model.armature = np.array([float(j.link.motor_inertia) for j in robot.joints])
            return robot, model
        from importlib.metadata import distribution

        share = distribution("example-robot-data").locate_file("cmeel.prefix/share")
        path = Path(str(share)) / "example-robot-data/robots/panda_description/urdf/panda.urdf"
        robot = symkin.load_robot(path, tip="panda_hand_tcp")
    full = pin.buildModelFromUrdf(str(path))
    chain = [joint.name for joint in robot.joints]
    others = [full.getJointId(n) for n in full.names[1:] if n not in chain]
    return robot, pin.buildReducedModel(full, others, pin.neutral(full))


@dataclass
class Built:
    """One robot: symkin's generated code (built) and Pinocchio's model of the same arm."""

    name: str
    robot: object
    pin_model: object
    ext: object
    casadi_module: object
    kernel_ops: int
    directory: Path
    parameters: np.ndarray
    loops: dict[tuple[str, int], Path] = field(default_factory=dict)


def build(name: str, directory: Path) -> Built:
    from symkin.generate import files_for_robot
    from symkin.output_folder import write_folder
    from symkin.runtime.extension import build_extension, load_extension

    robot, pin_model = robot_pair(name)
    assert pin_model.nq == pin_model.nv == robot.dof, "joints with cos/sin coordinates"
    _progress(f"{name}: deriving and generating the derivative kernels ...")
    kernels: list = []
    files = files_for_robot(robot, ("c", "python", "casadi"), derivatives=True)
    write_folder(directory, files)
    header = (directory / "c" / f"{robot.name}.h").read_text()
    line = next(x for x in header.splitlines() if "inverse_dynamics_derivatives:" in x)
    kernels.append(int(line.split(":")[1].split()[0]))
    extension = build_extension(
        directory / "python" / f"{robot.name}_ext.c", directory / "c" / f"{robot.name}.c"
    )
    return Built(
        name=name,
        robot=robot,
        pin_model=pin_model,
        ext=load_extension(extension),
        casadi_module=load_module(directory / "casadi" / f"{robot.name}_casadi.py"),
        kernel_ops=kernels[0],
        directory=directory,
        parameters=np.array(list(robot.parameter_values().values()), dtype=float),
    )


# --------------------------------------------------------------------------- CasADi


def arithmetic_instructions(function) -> int:
    """Instructions of an SX function that compute (no inputs, outputs or constants)."""
    import casadi

    bookkeeping = {casadi.OP_INPUT, casadi.OP_OUTPUT, casadi.OP_CONST, casadi.OP_PARAMETER}
    return sum(
        1 for k in range(function.n_instructions()) if function.instruction_id(k) not in bookkeeping
    )


def _axis_rotation(casadi, axis: np.ndarray, angle):
    """Rodrigues: I + sin q [a]x + (1 - cos q) [a]x^2 (constant unit axis a)."""
    cross = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return (
        casadi.DM.eye(3)
        + casadi.sin(angle) * casadi.DM(cross)
        + (1 - casadi.cos(angle)) * casadi.DM(cross @ cross)
    )


def _joint_axis(joint) -> tuple[str, np.ndarray]:
    kind = joint.shortname()
    for letter, axis in zip("XYZ", np.eye(3), strict=True):
        if kind in (f"JointModelR{letter}", f"JointModelRUB{letter}"):
            return "revolute", axis
        if kind == f"JointModelP{letter}":
            return "prismatic", axis
    if kind == "JointModelRevoluteUnaligned":
        return "revolute", np.array(joint.axis)
    if kind == "JointModelPrismaticUnaligned":
        return "prismatic", np.array(joint.axis)
    raise SystemExit(f"joint type {kind} is not in the bench's RNEA")


def casadi_rnea(pin_model, q, dq, ddq):
    """tau by the textbook recursive Newton–Euler in CasADi SX, link frames (Luh, Walker &
    Paul 1980), from Pinocchio's joint placements, axes and inertias; no symkin code."""
    import casadi

    n = pin_model.nv
    w = dw = casadi.SX.zeros(3)
    dv = casadi.SX(-np.array(pin_model.gravity.linear))
    frames = []
    for i in range(1, n + 1):
        kind, axis = _joint_axis(pin_model.joints[i])
        placement = pin_model.jointPlacements[i]
        rotation, offset = casadi.DM(placement.rotation), casadi.DM(placement.translation)
        a = casadi.DM(axis)
        if kind == "revolute":
            rotation = rotation @ _axis_rotation(casadi, axis, q[i - 1])
        else:
            offset = offset + casadi.DM(placement.rotation) @ a * q[i - 1]
        back = rotation.T
        dv = back @ (dv + casadi.cross(dw, offset) + casadi.cross(w, casadi.cross(w, offset)))
        w_parent = back @ w
        if kind == "revolute":
            w = w_parent + a * dq[i - 1]
            dw = back @ dw + a * ddq[i - 1] + casadi.cross(w_parent, a * dq[i - 1])
        else:
            w, dw = w_parent, back @ dw
            dv = dv + 2 * casadi.cross(w, a * dq[i - 1]) + a * ddq[i - 1]
        inertia = pin_model.inertias[i]
        com, mass = casadi.DM(inertia.lever), inertia.mass
        body = casadi.DM(inertia.inertia)
        force = mass * (dv + casadi.cross(dw, com) + casadi.cross(w, casadi.cross(w, com)))
        moment = body @ dw + casadi.cross(w, body @ w) + casadi.cross(com, force)
        frames.append((kind, a, rotation, offset, force, moment))
    tau = [None] * n
    f = m = casadi.SX.zeros(3)
    for i in reversed(range(n)):
        kind, a, rotation, offset, force, moment = frames[i]
        if i + 1 < n:
            child_rotation, child_offset = frames[i + 1][2], frames[i + 1][3]
            carried = child_rotation @ f
            m = moment + child_rotation @ m + casadi.cross(child_offset, carried)
            f = force + carried
        else:
            f, m = force, moment
        tau[i] = casadi.dot(a, m if kind == "revolute" else f)
        tau[i] += pin_model.armature[i] * ddq[i]
    return casadi.vertcat(*tau)


@dataclass
class Counts:
    symkin_kernel: int  # SymPy count_ops after CSE (generated headers)
    symkin_casadi: int  # the same kernel as a CasADi function, CasADi's count
    ad_of_symkin: int
    ad_of_rnea: int


def casadi_functions(b: Built):
    """The AD functions (q, dq, ddq|tau, p) -> (J_q^T, J_dq^T[, J_tau^T]) and the counts.

    The Jacobians are dense and transposed, so that CasADi's column-major storage is
    symkin's row-major layout (the C loop compares checksums)."""
    import casadi

    n, n_p = b.robot.dof, len(b.robot.parameters)
    q, dq, third = (casadi.SX.sym(s, n) for s in ("q", "dq", "x"))
    p = casadi.SX.sym("p", n_p)
    tau = b.casadi_module.inverse_dynamics_function()(q, dq, third, p)
    ad_tau = casadi.Function(
        f"{b.robot.name}_ad",
        [q, dq, third, p],
        [casadi.densify(casadi.jacobian(tau, x).T) for x in (q, dq)],
    )
    rnea = casadi_rnea(b.pin_model, q, dq, third)
    ad_rnea = casadi.Function(
        "ad_rnea", [q, dq, third], [casadi.jacobian(rnea, q), casadi.jacobian(rnea, dq)]
    )
    ddq = b.casadi_module.forward_dynamics_function()(q, dq, third, p)
    ad_forward = casadi.Function(
        f"{b.robot.name}_ad",
        [q, dq, third, p],
        [casadi.densify(casadi.jacobian(ddq, x).T) for x in (q, dq, third)],
    )
    ours = b.casadi_module.inverse_dynamics_derivatives_function()
    counts = Counts(
        symkin_kernel=b.kernel_ops,
        symkin_casadi=arithmetic_instructions(ours),
        ad_of_symkin=arithmetic_instructions(ad_tau),
        ad_of_rnea=arithmetic_instructions(ad_rnea),
    )
    return {"tau": ad_tau, "rnea": ad_rnea, "forward": ad_forward}, counts


# --------------------------------------------------------------------------- checks


def check(b: Built, ad: dict, rng: np.random.Generator) -> float:
    """Largest relative difference of symkin (extension) to Pinocchio and to the AD functions
    at random states; :class:`CheckError` past :data:`TOLERANCE`."""
    import pinocchio as pin

    data = b.pin_model.createData()
    worst = 0.0

    def compare(what: str, ours, theirs) -> None:
        nonlocal worst
        ours, theirs = np.asarray(ours, dtype=float), np.asarray(theirs, dtype=float)
        error = float(np.abs(ours - theirs).max()) / max(1.0, float(np.abs(theirs).max()))
        if not error <= TOLERANCE:
            raise CheckError(f"{b.name} {what}: symkin differs by {error:.3g} (relative)")
        worst = max(worst, error)

    for _ in range(10):
        q, dq, ddq = rng.uniform(-1.0, 1.0, (3, b.robot.dof)) * np.array([[np.pi], [2], [5]])
        tau, dtau_dq, dtau_ddq = b.ext.inverse_dynamics_derivatives(q, dq, ddq, b.parameters)
        pin.computeRNEADerivatives(b.pin_model, data, q, dq, ddq)
        compare("dtau/dq vs Pinocchio", dtau_dq, data.dtau_dq)
        compare("dtau/ddq vs Pinocchio", dtau_ddq, data.dtau_dv)
        compare("tau vs Pinocchio", tau, pin.rnea(b.pin_model, data, q, dq, ddq))
        by_q, by_dq = (np.array(m) for m in ad["tau"](q, dq, ddq, b.parameters))
        compare("dtau/dq vs CasADi AD", dtau_dq, by_q.T)  # the AD outputs are transposed
        compare("dtau/ddq vs CasADi AD", dtau_ddq, by_dq.T)
        by_q, by_dq = (np.array(m) for m in ad["rnea"](q, dq, ddq))
        compare("dtau/dq vs the CasADi RNEA's AD", dtau_dq, by_q)
        compare("dtau/ddq vs the CasADi RNEA's AD", dtau_ddq, by_dq)
        forward = b.ext.forward_dynamics_derivatives(q, dq, tau, b.parameters)
        pin.computeABADerivatives(b.pin_model, data, q, dq, tau)
        compare("ddq vs Pinocchio", forward[0], ddq)
        compare("dddq/dq vs Pinocchio", forward[1], data.ddq_dq)
        compare("dddq/ddq vs Pinocchio", forward[2], data.ddq_dv)
        inverse = np.triu(data.Minv) + np.triu(data.Minv, 1).T
        compare("dddq/dtau vs Pinocchio", forward[3], inverse)
    return worst


# --------------------------------------------------------------------------- C loop


def build_loops(b: Built, ad: dict, cc: str) -> None:
    """The harness against symkin's C (kernel 1: inverse, 2: forward dynamics' derivatives)
    and against CasADi's generated C of the AD functions."""
    import casadi

    name, n_p = b.robot.name, len(b.robot.parameters)
    defines = (f"-DROBOT={name}", f"-DDOF={b.robot.dof}", f"-DN_P={n_p}")
    for kernel, key in ((1, "tau"), (2, "forward")):
        folder = b.directory / f"casadi_c{kernel}"
        folder.mkdir()
        generator = casadi.CodeGenerator(f"casadi_{name}.c", {"with_header": True})
        generator.add(ad[key])
        generator.generate(f"{folder}/")
        b.loops["symkin", kernel] = compile_c(
            cc, FLAGS, [HARNESS, b.directory / "c" / f"{name}.c"],
            b.directory / f"loop_symkin{kernel}", f"-I{b.directory / 'c'}",
            f'-DHEADER="{name}.h"', f"-DKERNEL={kernel}", *defines,
        )  # fmt: skip
        b.loops["casadi", kernel] = compile_c(
            cc, FLAGS, [HARNESS, folder / f"casadi_{name}.c"], b.directory / f"loop_casadi{kernel}",
            f"-I{folder}", f'-DHEADER="casadi_{name}.h"', f"-DKERNEL={kernel}",
            "-DBENCH_CASADI", *defines,
        )  # fmt: skip


def c_loop(builds: list[Built], settings) -> dict[tuple[str, str, int], Result]:
    """ns per call, ``{(robot, "symkin" | "casadi", kernel): result}``, rounds interleaved."""
    results: dict[tuple[str, str, int], Result] = {}
    checksums: dict[tuple[str, str, int], float] = {}
    for round_ in range(settings.c_rounds):
        for b in builds:
            arguments = [str(settings.c_calls // 4), str(settings.c_repeats)]
            arguments += [repr(float(v)) for v in b.parameters]
            for (impl, kernel), executable in b.loops.items():
                key = (b.name, impl, kernel)
                result = results.setdefault(key, Result(f"{impl} {b.name} {kernel}"))
                done = subprocess.run(
                    [str(executable), *arguments], capture_output=True, text=True, check=True
                )
                for line in done.stdout.splitlines():
                    word, value = line.split()
                    if word == "ns_per_call":
                        result.values.append(float(value))
                    else:
                        checksums[key] = float(value)
        _progress(f"C loop round {round_ + 1}/{settings.c_rounds}")
    for b in builds:
        for kernel in (1, 2):
            ours, theirs = checksums[b.name, "symkin", kernel], checksums[b.name, "casadi", kernel]
            if not abs(ours - theirs) <= 1e-6 * max(1.0, abs(ours)):
                raise CheckError(f"{b.name} kernel {kernel}: C checksums {ours!r} != {theirs!r}")
    return results


# --------------------------------------------------------------------------- Python


def python_timings(builds: list[Built], settings, rng) -> dict[str, Result]:
    """ns per call from Python: symkin's extension against Pinocchio's bindings."""
    import pinocchio as pin

    contenders: list[Contender] = []
    namespace: dict = {"pin": pin}
    inputs_by_robot = {}
    for b in builds:
        data = b.pin_model.createData()
        namespace |= {f"{b.name}_ext": b.ext, f"{b.name}_model": b.pin_model}
        namespace |= {f"{b.name}_data": data, f"{b.name}_p": b.parameters}
        states = rng.uniform(-1.0, 1.0, (SAMPLES, 3, b.robot.dof)) * np.array([[np.pi], [2], [5]])
        inputs_by_robot[b.name] = [
            (s[0].copy(), s[1].copy(), s[2].copy(), pin.rnea(b.pin_model, data, *s)) for s in states
        ]
        n = b.name
        contenders += [
            Contender(
                Result(f"{n}: symkin `ext.inverse_dynamics_derivatives(q, dq, ddq)`", ours=True),
                f"{n}_ext.inverse_dynamics_derivatives(q[0], q[1], q[2], {n}_p)",
            ),
            Contender(
                Result(f"{n}: Pinocchio `computeRNEADerivatives(model, data, q, v, a)`"),
                f"pin.computeRNEADerivatives({n}_model, {n}_data, q[0], q[1], q[2])",
            ),
            Contender(
                Result(f"{n}: symkin `ext.forward_dynamics_derivatives(q, dq, tau)`", ours=True),
                f"{n}_ext.forward_dynamics_derivatives(q[0], q[1], q[3], {n}_p)",
            ),
            Contender(
                Result(f"{n}: Pinocchio `computeABADerivatives(model, data, q, v, tau)`"),
                f"pin.computeABADerivatives({n}_model, {n}_data, q[0], q[1], q[3])",
            ),
        ]
    peers = Peers(namespace)
    for b in builds:
        own = [c for c in contenders if c.statement.startswith((f"{b.name}_", "pin.compute"))]
        own = [c for c in own if f"{b.name}_" in c.statement]
        time_contenders(
            own, inputs_by_robot[b.name], peers, settings.py_repeats, settings.py_budget_s,
            settings.py_batch_ns, f"Python per call ({b.name})",
        )  # fmt: skip
    return {c.result.label: c.result for c in contenders}


# --------------------------------------------------------------------------- report


def _ns(result: Result | None) -> str:
    if result is None or result.median is None:
        return "—" if result is None or result.error is None else result.error
    return f"{result.median:,.0f}" if result.median >= 100 else f"{result.median:.1f}"


def _ratio(theirs: Result | None, ours: Result | None) -> str:
    if not theirs or not ours or theirs.median is None or ours.median is None:
        return "—"
    return f"{theirs.median / ours.median:.1f}×"


def render(builds, counts, c_results, py_results, worst, loads, settings) -> str:
    today = datetime.date.today().isoformat()
    lines = [
        f"Measured on {today}: {cpu_model()}, {os.cpu_count()} cores (shared with other "
        f"jobs during the run); Python {platform.python_version()}, symkin "
        f"{version('symkin')}, Pinocchio {version('pin')}, CasADi {version('casadi')}, "
        f"{compiler_version(compiler())} -O2. Load average (1 min) at the start and end of the "
        f"run: {loads[0]:.1f} and {loads[1]:.1f}. Times are CPU nanoseconds per call, median "
        f"of {settings.c_rounds}×{settings.c_repeats} C repeats and up to {settings.py_repeats} "
        f"interleaved Python repeats. Largest relative difference to Pinocchio and to CasADi's "
        f"AD at 10 random states per robot: {worst:.1e}. Generated by "
        "`bench/derivatives_speed.py`.",
        "",
        "| robot | quantity | symkin C loop | CasADi AD, its C | symkin from Python "
        "(extension) | Pinocchio from Python | Pinocchio / symkin (Python) |",
        "| --- | --- | ---: | ---: | ---: | ---: | ---: |",
    ]
    for b in builds:
        label = ROBOTS[b.name]
        for kernel, quantity, ours, theirs in (
            (1, "tau, dtau/dq, dtau/ddq", "inverse_dynamics_derivatives", "computeRNEADerivatives"),
            (
                2,
                "ddq, dddq/dq, dddq/ddq, M^-1",
                "forward_dynamics_derivatives",
                "computeABADerivatives",
            ),
        ):
            mine = next(
                r for k, r in py_results.items() if k.startswith(f"{b.name}: symkin `ext.{ours}")
            )
            peer = next(r for k, r in py_results.items() if theirs in k and k.startswith(b.name))
            lines.append(
                f"| {label} | {quantity} | {_ns(c_results[b.name, 'symkin', kernel])} | "
                f"{_ns(c_results[b.name, 'casadi', kernel])} | {_ns(mine)} | {_ns(peer)} | "
                f"{_ratio(peer, mine)} |"
            )
    lines += [
        "",
        "Operations for tau, dtau/dq and dtau/ddq (fewer is better):",
        "",
        "| robot | symkin kernel (`count_ops` after CSE, as in the headers) | symkin kernel as a "
        "CasADi function (CasADi's count) | CasADi AD of symkin's CasADi tau | CasADi AD of an "
        "independent RNEA (numbers folded) |",
        "| --- | ---: | ---: | ---: | ---: |",
    ]
    for b in builds:
        c = counts[b.name]
        lines.append(
            f"| {ROBOTS[b.name]} | {c.symkin_kernel} | {c.symkin_casadi} | {c.ad_of_symkin} "
            f"| {c.ad_of_rnea} |"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats")
    parser.add_argument("--no-write", action="store_true", help="print, do not edit the docs")
    parser.add_argument("--docs", type=Path, default=DOCS)
    args = parser.parse_args(argv)
    settings = QUICK if args.quick else FULL
    rng = np.random.default_rng(2026)
    loads = [os.getloadavg()[0]]
    cc = compiler()
    with tempfile.TemporaryDirectory(prefix="symkin-derivatives-") as temporary:
        builds, counts, worst = [], {}, 0.0
        for name in ROBOTS:
            b = build(name, Path(temporary) / name)
            ad, counts[name] = casadi_functions(b)
            worst = max(worst, check(b, ad, rng))
            build_loops(b, ad, cc)
            builds.append(b)
        c_results = c_loop(builds, settings)
        py_results = python_timings(builds, settings, rng)
        loads.append(os.getloadavg()[0])
        table = render(builds, counts, c_results, py_results, worst, loads, settings)
    print(table)
    if not args.no_write:
        write_docs(table, args.docs, MARKERS, "Derivative kernels")
    return 0


if __name__ == "__main__":
    sys.exit(main())
