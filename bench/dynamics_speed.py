"""Dynamics of the PUMA 560 and the Panda: symkin's derivation time, the size of its generated
kernels and the speed of its generated inverse dynamics, against Pinocchio, Robotics Toolbox,
CasADi and the issue's SymPyBotics figures.

In one run, on the same machine:

* **Derivation time**, each repetition in a fresh Python process (``derivation_time.measure``),
  CPU seconds of the child:

  - *full dynamics*: ``symkin.derive(robot)`` + ``symkin.kernels.dynamics_kernels(model)``
    (M, G, c, C, tau), then the NumPy, C and CasADi modules of those kernels (which include
    forward dynamics) from ``emit_numpy``, ``emit_c``, ``emit_casadi``;
  - *the tau kernel alone*: the Newton–Euler recursion ``model.inverse_dynamics_recursion`` and
    its kernel (one CSE);
  - *Lagrange*: ``symkin.derive(robot).lagrange`` (M, C, c, G), under a CPU-time limit.

  Each for several variants of the catalogue robot: inertial data as numbers (the catalogue
  files carry Corke's for the PUMA and Gaz et al.'s for the Panda) or as symbols (``pi`` inputs
  of the generated code), and geometry as the file's parameter symbols (``p`` inputs) or
  substituted by their values (as in the issue's SymPyBotics figures).
* **Operation counts** of the generated kernels (``Kernel.operation_counts["total"]``, the
  figures in the generated files' headers), next to the issue's figures for SymPyBotics and
  Lagrange in SymPy, SymEngine and ``sympy.physics.mechanics``.  SymPyBotics itself is not on
  PyPI and cannot be installed here; its figures are quoted, not measured.
* **Inverse and forward dynamics per call in a C loop**: ``bench/dynamics_speed_loop.c`` calls
  the generated ``<robot>_inverse_dynamics`` and ``<robot>_forward_dynamics`` over 65,536
  precomputed states, and the C that ``casadi.CodeGenerator`` writes for the generated CasADi
  module's ``inverse_dynamics_function()`` and ``forward_dynamics_function()`` (CasADi printing
  symkin's graph) and for the independent CasADi model of ``bench/casadi_peer.py`` (Newton–Euler
  from the DH table, forward dynamics by ``casadi.solve``); all compiled with ``gcc -O2``
  (symkin's extension flags) and alternated round by round (``bench/c_loop.py``), each harness
  run's peak resident set recorded.
  Three generated codes (``BUILDS``): the PUMA 560 with its parameters as input ``p``, the PUMA
  560 with numeric parameters (``Robot.with_parameter_values()``: no ``p``, base inertial
  parameters; its torques are first checked against the code with ``p``), and the Panda with
  its parameters as input ``p`` (checked against Robotics Toolbox's ``models.DH.Panda``).
* **Inverse dynamics per call from Python** (PUMA 560): symkin's generated CPython extension
  (compiled with ``symkin.runtime.extension.build_extension``, as ``symkin derive`` does),
  symkin's C through ctypes, the generated NumPy module, CasADi (``Function`` call and its C through
  ctypes), Pinocchio ``rnea`` on a model built from the same DH table and inertial data
  (``tests/test_dynamics_oracles.py``),
  and Robotics Toolbox ``DH.Puma560().rne`` (its C extension ``frne``); and in batches of
  10,000 states: symkin's batched C (ctypes and the extension), the NumPy module and Robotics
  Toolbox.

Before any timing, every implementation's torques are compared with symkin's C at random
states (the script stops if one differs by more than 1e-9 relative); the largest difference is
printed with the table.  Python timings reuse ``codegen_speed``'s interleaved, CPU-time
repeats.  The script prints a Markdown table and writes it into ``docs/benchmarks.md`` between
``<!-- dynamics:begin -->`` and ``<!-- dynamics:end -->``.  No test passes or fails on it.

Usage::

    .venv/bin/python bench/dynamics_speed.py            # full run, 3 to 5 minutes
    .venv/bin/python bench/dynamics_speed.py --quick    # fewer repeats, about 1 minute
    .venv/bin/python bench/dynamics_speed.py --quick --no-write
"""

from __future__ import annotations

import argparse
import contextlib
import ctypes
import dataclasses
import datetime
import importlib.util
import json
import os
import platform
import sys
import tempfile
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from c_loop import METHOD, Job, Run, casadi_c, compile_harness, peer_targets, run_rounds
from c_loop import table as c_loop_rows
from codegen_speed import (
    FULL,
    QUICK,
    CheckError,
    Contender,
    Peers,
    Result,
    Settings,
    casadi_c_function,
    check_close,
    compiler,
    compiler_version,
    load_module,
    ns_text,
    ratio_text,
    result_cells,
    shared_libraries,
    time_contenders,
    write_docs,
)
from derivation_time import (
    CLOCK,
    Runs,
    _time_limit,
    _TimeLimit,
    cpu_model,
    measure,
    seconds_text,
    timing_cell,
    version,
)
from symkin.runtime.extension import OPTIMISATION_FLAGS, build_extension, load_extension

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs" / "benchmarks.md"
BEGIN = "<!-- dynamics:begin -->"
END = "<!-- dynamics:end -->"
HARNESS = Path(__file__).resolve().with_name("dynamics_speed_loop.c")
SAMPLES = 65_536  # distinct states the per-call measurements walk through
BATCH = 10_000  # states in the batch measurements
CHECK_STATES = 20
TOLERANCE = 1e-9  # largest difference allowed, relative to the largest torque (at least 1)

# (robot, inertial data, geometry): "numeric" inertia is the catalogue file's, "symbolic" has the
# file's link data removed; "numeric" geometry substitutes the file's parameter values for its
# symbols.
VARIANTS = (
    ("puma560", "numeric", "symbolic"),
    ("puma560", "symbolic", "symbolic"),
    ("puma560", "symbolic", "numeric"),
    ("puma560", "numeric", "numeric"),
    ("panda", "numeric", "symbolic"),
    ("panda", "symbolic", "symbolic"),
    ("panda", "symbolic", "numeric"),
    ("panda", "numeric", "numeric"),
)
KERNELS = ("mass_matrix", "gravity", "coriolis", "coriolis_matrix", "inverse_dynamics")

# The generated code the C loop times, {key: (its variant in VARIANTS, label)}. With numeric
# inertia and numeric geometry the PUMA 560 is the catalogue robot's ``with_parameter_values()``
# (``symkin derive puma560 --numeric-parameters``): no ``p`` input, the recursion on base
# inertial parameters.
BUILDS = {
    "puma560": (("puma560", "numeric", "symbolic"), "PUMA 560, parameters as input `p`"),
    "puma560-numeric": (
        ("puma560", "numeric", "numeric"),
        "PUMA 560, numeric parameters (base parameters)",
    ),
    "panda": (("panda", "numeric", "symbolic"), "Panda, parameters as input `p`"),
}
PUMA_BUILDS = ("puma560", "puma560-numeric")
C_LOOP_KERNELS = ("inverse_dynamics", "forward_dynamics")
C_LOOP_LABELS = {"inverse_dynamics": "tau", "forward_dynamics": "forward dynamics"}

# The issue's figures (SymPy 1.14, the same kind of 2-core machine, PUMA 560 with numeric
# geometry and symbolic inertia); SymPyBotics is not on PyPI, so they are quoted, not measured.
ISSUE_DERIVATION = (
    ("SymPyBotics (Newton–Euler + incremental CSE): tau", "0.44 s"),
    ("SymPyBotics: tau, g, c, C, M, regressor", "15.7 s (the C matrix alone 9.3 s); Panda 22.6 s"),
    ("plain SymPy Lagrange (M, C, G), no simplification", "27 s"),
    ("the same algorithm in SymEngine", "0.07 s (Panda 0.24 s)"),
    ("`sympy.physics.mechanics` Lagrange", "107 s (Panda: did not finish in 600 s)"),
    ("SymPy Lagrange with `trigsimp`", "did not finish in 600 s"),
)
ISSUE_OPERATIONS = (
    ("SymPyBotics, inverse dynamics (tau)", "962 (Panda 860; M 780 / 1454)"),
    ("plain SymPy Lagrange, after CSE", "7187"),
    ("SymEngine Lagrange, after CSE", "6372"),
    ("`sympy.physics.mechanics` Lagrange, after CSE", "6275"),
    ("CasADi hand-written RNEA with numeric parameters", "528 instructions"),
)
ISSUE_PER_CALL = (
    "Pinocchio `rnea` from Python 1.5–1.75 µs; CasADi-generated C in a C loop 205 ns "
    "(via ctypes 1.5 µs); SymPyBotics C 362 ns in a loop; Robotics Toolbox `rne` (C) 19 µs"
)
SYMPYBOTICS_OPERATIONS = {"puma560": 962, "panda": 860}

# The issue's targets.
TARGET_DERIVATION_S = {"puma560": 3.0, "panda": 10.0}
TARGET_NUMERIC_OPERATIONS = 400
TARGET_C_NS = 150.0


def _progress(text: str) -> None:
    print(text, file=sys.stderr, flush=True)


# --------------------------------------------------------------------------- robots


def variant_name(robot: str, inertia: str, geometry: str) -> str:
    return f"{robot}:{inertia}:{geometry}"


def load_catalogue_robot(name: str):
    """A catalogue robot, without the PUMA's documented triangle-inequality warning."""
    import symkin
    from symkin.errors import RobotWarning

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RobotWarning)
        return symkin.load_robot(name)


def robot_variant(name: str, inertia: str, geometry: str):
    """The catalogue robot with symbolic inertia and/or its parameters substituted."""
    robot = load_catalogue_robot(name)
    if inertia == "symbolic":
        robot = dataclasses.replace(
            robot, joints=tuple(dataclasses.replace(j, link=None) for j in robot.joints)
        )
    elif any(j.link is None for j in robot.joints):
        raise SystemExit(f"{name}: the catalogue file has no inertial data")
    return robot.with_parameter_values() if geometry == "numeric" else robot


# --------------------------------------------------------------------------- children
# Each child prints exactly one JSON object on its last line of stdout.


def _child_full(robot) -> dict:
    from symkin import derive
    from symkin.emit.c import emit_c
    from symkin.emit.casadi import emit_casadi
    from symkin.emit.numpy import emit_numpy
    from symkin.kernels import dynamics_kernels

    start = CLOCK()
    kernels = dynamics_kernels(derive(robot))
    derived = CLOCK()
    emit_numpy(robot, kernels)
    emit_c(robot, kernels)
    emit_casadi(robot, kernels)
    end = CLOCK()
    return {
        "seconds": end - start,
        "derive_s": derived - start,
        "emit_s": end - derived,
        "ops": {k.name: k.operation_counts["total"] for k in kernels},
    }


def _child_tau(robot) -> dict:
    from symkin import derive
    from symkin.kernels import dynamics_inputs, kernel_from_assignments

    start = CLOCK()
    model = derive(robot)
    assignments, tau = model.inverse_dynamics_recursion
    kernel_from_assignments(
        "inverse_dynamics",
        "inverse dynamics",
        dynamics_inputs(model, "dq", "ddq"),
        assignments,
        [("tau", tau, "joint torques", "vector")],
    )
    return {"seconds": CLOCK() - start}


def _child_lagrange(robot) -> dict:
    from symkin import derive

    start = CLOCK()
    derive(robot).lagrange  # noqa: B018 - a cached property: this derives it
    return {"seconds": CLOCK() - start}


CHILDREN = {"full": _child_full, "tau": _child_tau, "lagrange": _child_lagrange}


def _child(argv: list[str]) -> None:
    kind, name, limit = argv[0], argv[1], float(argv[2])
    robot = robot_variant(*name.split(":"))
    try:
        with _time_limit(limit):
            result = CHILDREN[kind](robot)
    except _TimeLimit:
        result = {"timeout": limit}
    print(json.dumps(result))


def derivations(repeat: int, timeout: float) -> dict[tuple[str, str], Runs]:
    """``{(kind, variant name): runs}`` for every child kind and variant."""
    script = Path(__file__)
    return {
        (kind, variant_name(*variant)): measure(
            kind, variant_name(*variant), repeat, timeout, script
        )
        for variant in VARIANTS
        for kind in CHILDREN
    }


# --------------------------------------------------------------------------- building


@dataclass
class Built:
    """One robot's generated code, built: the C loop for symkin and CasADi, shared libraries."""

    label: str
    robot: object  # symkin.robot.Robot
    parameters: np.ndarray  # p, file order
    numpy_module: object
    casadi_module: object
    loops: dict[tuple[str, str], Path]  # (kernel, implementation) -> C-loop executable
    lib_ours: Path
    lib_casadi: Path
    directory: Path  # the generated files
    peer_functions: list  # the independent CasADi model's tau and FD (casadi.Function)


def build(directory: Path, key: str, cc: str, flags: tuple[str, ...]) -> Built:
    """The code of ``BUILDS[key]``, generated into ``directory`` and compiled: the C loops of
    ``C_LOOP_KERNELS`` for symkin's C, CasADi's C of symkin's graph and of the independent
    model, and symkin's and CasADi's C as shared libraries."""
    import casadi_peer
    from symkin.generate import files_for_robot
    from symkin.output_folder import write_folder

    variant, label = BUILDS[key]
    robot = robot_variant(*variant)
    name = robot.name
    write_folder(directory, files_for_robot(robot, ("numpy", "c", "casadi", "python")))
    numpy_module = load_module(directory / "numpy" / f"{name}_kinematics.py")
    casadi_module = load_module(directory / "casadi" / f"{name}_casadi.py")
    if any(j.link is None for j in robot.joints):
        raise SystemExit(f"{name}: no inertial data to time it with")

    graph_functions = [casadi_module.inverse_dynamics_function()]
    graph_functions.append(casadi_module.forward_dynamics_function())
    peer_functions = casadi_peer.functions(robot, C_LOOP_KERNELS)
    sources = {
        "symkin": directory / "c" / f"{name}.c",
        "graph": casadi_c(graph_functions, directory / "casadi_c", f"casadi_{name}"),
        "peer": casadi_c(peer_functions, directory / "peer_c", f"peer_{name}"),
    }
    n_p = len(robot.parameters)
    defines = (f"-DROBOT={name}", f"-DDOF={robot.dof}", f"-DN_P={n_p}", "-DN_PI=0")
    loops = {
        (kernel, impl): compile_harness(
            cc, flags, HARNESS, source, directory / f"loop_{kernel}_{impl}", *defines,
            f"-DKERNEL=_{kernel}",
        )
        for kernel in C_LOOP_KERNELS
        for impl, source in sources.items()
    }  # fmt: skip
    libraries = shared_libraries(cc, flags, directory, name)
    return Built(
        label=label,
        robot=robot,
        parameters=np.array(list(robot.parameter_values().values()), dtype=float),
        numpy_module=numpy_module,
        casadi_module=casadi_module,
        loops=loops,
        lib_ours=libraries.ours,
        lib_casadi=libraries.casadi,
        directory=directory,
        peer_functions=peer_functions,
    )


# --------------------------------------------------------------------------- C loop


def c_loop(builds: dict[str, Built], settings: Settings) -> dict[tuple[str, str, str], Run]:
    """ns per call in a C loop, ``{(build key, kernel, implementation): run}``, alternated."""
    jobs = [
        Job(key, kernel, impl, (str(executable), str(settings.c_calls), str(settings.c_repeats),
                                *(repr(float(v)) for v in b.parameters)))
        for key, b in builds.items()
        for (kernel, impl), executable in b.loops.items()
    ]  # fmt: skip
    return run_rounds(jobs, settings.c_rounds)


# --------------------------------------------------------------------------- checks and peers


def random_states(rng: np.random.Generator, count: int, dof: int) -> np.ndarray:
    """``(count, 3, dof)``: q in [-pi, pi), dq in [-2, 2), ddq in [-5, 5), like the C harness."""
    scale = np.array([np.pi, 2.0, 5.0])[:, None]
    return rng.uniform(-1.0, 1.0, (count, 3, dof)) * scale


@dataclass
class Checked:
    """Largest torque difference to symkin's C of every implementation, and notes."""

    differences: dict[str, float] = dataclasses.field(default_factory=dict)
    notes: list[str] = dataclasses.field(default_factory=list)

    def compare(self, what: str, actual, expected) -> None:
        scale = max(1.0, float(np.abs(expected).max()))
        worst = check_close(what, actual, expected, TOLERANCE * scale)
        self.differences[what] = max(worst, self.differences.get(what, 0.0))


def symkin_c(b: Built):
    """symkin's ``<robot>_inverse_dynamics`` and its ``_batch`` twin through ctypes: q, dq,
    ddq, p (none without parameters) and tau."""
    lib = ctypes.CDLL(str(b.lib_ours))
    name = b.robot.name
    arrays = 5 if b.robot.parameters else 4
    single = lib[f"{name}_inverse_dynamics"]
    single.argtypes = [ctypes.c_void_p] * arrays
    single.restype = None
    batch = lib[f"{name}_inverse_dynamics_batch"]
    batch.argtypes = [ctypes.c_size_t] + [ctypes.c_void_p] * arrays
    batch.restype = None
    return single, batch


def check_numeric_parameters(
    b: Built, reference: Built, rng: np.random.Generator, checked: Checked
) -> None:
    """The code with the parameters folded in (base parameters) against the code that takes them
    as ``p``: numeric parameters change the code, not the torques."""
    folded, _ = symkin_c(b)
    with_p, _ = symkin_c(reference)
    P = reference.parameters
    dof = b.robot.dof
    for q, dq, ddq in random_states(rng, CHECK_STATES, dof):
        tau, expected = np.empty(dof), np.empty(dof)
        pointers = (q.ctypes.data, dq.ctypes.data, ddq.ctypes.data)
        with_p(*pointers, P.ctypes.data, expected.ctypes.data)
        folded(*pointers, tau.ctypes.data)  # no parameters: no p argument
        checked.compare("puma560, numeric parameters (base parameters): symkin C", tau, expected)


def check_panda(b: Built, rng: np.random.Generator, checked: Checked) -> None:
    """The Panda's generated code against Robotics Toolbox's ``rne``, whose ``models.DH.Panda``
    carries the same inertial data (Gaz et al. 2019) as the catalogue file."""
    single, _ = symkin_c(b)
    P = b.parameters
    import roboticstoolbox as rtb

    panda = rtb.models.DH.Panda().nofriction(coulomb=True, viscous=True)
    for q, dq, ddq in random_states(rng, CHECK_STATES, b.robot.dof):
        tau = np.empty(b.robot.dof)
        pointers = (q.ctypes.data, dq.ctypes.data, ddq.ctypes.data, P.ctypes.data)
        single(*pointers, tau.ctypes.data)
        numpy_tau = b.numpy_module.inverse_dynamics(q, dq, ddq, P)
        checked.compare("panda: symkin NumPy module", numpy_tau, tau)
        checked.compare("panda: Robotics Toolbox `DH.Panda().rne`", panda.rne(q, dq, ddq), tau)


def check_casadi_dynamics(b: Built, rng: np.random.Generator, checked: Checked) -> None:
    """Both CasADi codes' tau and forward dynamics (CasADi of symkin's graph, the independent
    model) against symkin's C at random states."""
    lib = ctypes.CDLL(str(b.lib_ours))
    arrays = 5 if b.robot.parameters else 4
    ours = {}
    for kernel in C_LOOP_KERNELS:
        ours[kernel] = lib[f"{b.robot.name}_{kernel}"]
        ours[kernel].argtypes = [ctypes.c_void_p] * arrays
        ours[kernel].restype = None
    graph = {
        "inverse_dynamics": b.casadi_module.inverse_dynamics_function(),
        "forward_dynamics": b.casadi_module.forward_dynamics_function(),
    }
    peer = dict(zip(C_LOOP_KERNELS, b.peer_functions, strict=True))
    P, dof = b.parameters, b.robot.dof
    for state in random_states(rng, CHECK_STATES, dof):
        for kernel, function in ours.items():
            expected = np.empty(dof)
            pointers = [s.ctypes.data for s in state] + (
                [P.ctypes.data] if b.robot.parameters else []
            )
            function(*pointers, expected.ctypes.data)
            for what, f in (("CasADi of symkin's graph", graph), ("independent CasADi", peer)):
                actual = f[kernel](*state, P).full().ravel()
                checked.compare(f"{b.robot.name} ({b.label}): {what} {kernel}", actual, expected)


@contextlib.contextmanager
def python_fallback_fails(robot):
    """Robotics Toolbox's ``rne`` falls back to ``rne_python`` silently: make that an error."""

    def refuse(*args, **kwargs):
        raise CheckError("Robotics Toolbox `rne` fell back to its Python implementation")

    robot.rne_python = refuse
    try:
        yield
    finally:
        del robot.rne_python


def prepare_puma(b: Built, rng: np.random.Generator, checked: Checked) -> Peers:
    """The namespace the PUMA's Python-side statements use, every peer checked first."""
    import pinocchio as pin

    sys.path.insert(0, str(ROOT / "tests"))
    from test_dynamics_oracles import pinocchio_model

    dof = b.robot.dof
    single, batch = symkin_c(b)
    P = b.parameters
    ns: dict = {"np": np, "empty": np.empty, "np_dyn": b.numpy_module, "P": P}
    tau_buffer = np.empty(dof)
    ns.update(c_id=single, c_id_batch=batch, P_ptr=P.ctypes.data)
    ns.update(tau_buffer=tau_buffer, out_ptr=tau_buffer.ctypes.data)
    peers = Peers(ns)

    def ours(q, dq, ddq) -> np.ndarray:
        tau = np.empty(dof)
        single(q.ctypes.data, dq.ctypes.data, ddq.ctypes.data, P.ctypes.data, tau.ctypes.data)
        return tau

    # CasADi: the generated module's Function, and its generated C through ctypes.
    f_id = b.casadi_module.inverse_dynamics_function()
    cas_id = casadi_c_function(b.lib_casadi, f"{b.robot.name}_inverse_dynamics")
    ns.update(
        casadi_id=f_id,
        cas_id=cas_id,
        cas_arg=(ctypes.c_void_p * 4)(None, None, None, P.ctypes.data),
        cas_res=(ctypes.c_void_p * 1)(),
    )

    # symkin's CPython extension, compiled as `symkin derive` compiles it.
    name = b.robot.name
    ext = load_extension(
        build_extension(b.directory / "python" / f"{name}_ext.c", b.directory / "c" / f"{name}.c")
    )
    ns["ext"] = ext

    # Pinocchio on the model the dynamics tests use, with the rotor inertias as armature.
    pin_model = pinocchio_model(b.robot)[1]
    pin_model.armature = np.array([float(j.link.motor_inertia) for j in b.robot.joints])
    ns.update(pin=pin, model=pin_model, data=pin_model.createData())

    # Robotics Toolbox: Corke's PUMA with friction off (the catalogue file has none).
    import roboticstoolbox as rtb

    puma = rtb.models.DH.Puma560().nofriction(coulomb=True, viscous=True)
    ns["puma"] = puma

    numpy_id, rnea = b.numpy_module.inverse_dynamics, pin.rnea
    states = random_states(rng, CHECK_STATES, dof)
    for q, dq, ddq in states:
        tau = ours(q, dq, ddq)
        checked.compare("puma560: symkin NumPy module", numpy_id(q, dq, ddq), tau)
        checked.compare("puma560: symkin extension", ext.inverse_dynamics(q, dq, ddq), tau)
        checked.compare("puma560: CasADi `Function`", f_id(q, dq, ddq, P).full().ravel(), tau)
        out = np.empty(dof)
        ns["cas_arg"][0:3] = [q.ctypes.data, dq.ctypes.data, ddq.ctypes.data]
        ns["cas_res"][0] = out.ctypes.data
        cas_id(ns["cas_arg"], ns["cas_res"], None, None, 0)
        checked.compare("puma560: CasADi-generated C", out, tau)
        checked.compare("puma560: Pinocchio `rnea`", rnea(pin_model, ns["data"], q, dq, ddq), tau)
        with python_fallback_fails(puma):
            checked.compare("puma560: Robotics Toolbox `rne`", puma.rne(q, dq, ddq), tau)
    Q, DQ, DDQ = (np.ascontiguousarray(states[:, k]) for k in range(3))
    expected = np.array([ours(*s) for s in states])
    out = np.empty((CHECK_STATES, dof))
    pointers = (Q.ctypes.data, DQ.ctypes.data, DDQ.ctypes.data, P.ctypes.data, out.ctypes.data)
    batch(CHECK_STATES, *pointers)
    checked.compare("puma560: symkin batched C", out, expected)
    checked.compare("puma560: symkin NumPy module (batch)", numpy_id(Q, DQ, DDQ), expected)
    checked.compare("puma560: symkin extension (batch)", ext.inverse_dynamics(Q, DQ, DDQ), expected)
    with python_fallback_fails(puma):
        checked.compare("puma560: Robotics Toolbox `rne` (batch)", puma.rne(Q, DQ, DDQ), expected)
    checked.notes.append(
        "Robotics Toolbox's `rne` ran its C extension (`frne`) in every check: its fallback to "
        "`rne_python` was made to fail. Pinocchio's model is the one of "
        "`tests/test_dynamics_oracles.py`, with the rotor inertias as `armature`."
    )
    return peers


# --------------------------------------------------------------------------- Python timing


# Every statement's loop variable q holds one state (q, dq, ddq) and the addresses of its
# three arrays.
UNPACK = "x, v, a, ptr = q; "


def with_addresses(arrays: tuple[np.ndarray, ...]) -> tuple:
    """``(*arrays, addresses)``: a state as the timed statements unpack it."""
    arrays = tuple(np.ascontiguousarray(a) for a in arrays)
    return (*arrays, tuple(a.ctypes.data for a in arrays))


def per_call_contenders() -> tuple[list[Contender], Contender]:
    rows = [
        Contender(
            Result("symkin extension `inverse_dynamics(q, dq, ddq)`", ours=True),
            UNPACK + "ext.inverse_dynamics(x, v, a)",
        ),
        Contender(
            Result("ctypes on symkin's C (`puma560_inverse_dynamics`, fresh output)"),
            UNPACK + "tau = empty(6); "
            "c_id(x.ctypes.data, v.ctypes.data, a.ctypes.data, P_ptr, tau.ctypes.data)",
        ),
        Contender(
            Result("the same with the addresses of the arrays taken beforehand"),
            UNPACK + "c_id(*ptr, P_ptr, out_ptr)",
        ),
        Contender(
            Result("symkin NumPy module `inverse_dynamics(q, dq, ddq)`"),
            UNPACK + "np_dyn.inverse_dynamics(x, v, a)",
        ),
        Contender(
            Result("ctypes on CasADi C of symkin's graph (fresh output)"),
            UNPACK + "tau = empty(6); cas_arg[0] = x.ctypes.data; cas_arg[1] = v.ctypes.data; "
            "cas_arg[2] = a.ctypes.data; cas_res[0] = tau.ctypes.data; "
            "cas_id(cas_arg, cas_res, None, None, 0)",
        ),
        Contender(
            Result("CasADi `Function` of symkin's graph, `f(q, dq, ddq, p).full()`"),
            UNPACK + "casadi_id(x, v, a, P).full()",
        ),
        Contender(Result("Pinocchio `rnea`"), UNPACK + "pin.rnea(model, data, x, v, a)"),
        Contender(
            Result("Robotics Toolbox `DH.Puma560().rne(q, qd, qdd)` (C extension)"),
            UNPACK + "puma.rne(x, v, a)",
        ),
    ]
    empty = Contender(Result("empty loop iteration"), UNPACK.rstrip("; "))
    return rows, empty


def batch_contenders() -> list[Contender]:
    return [
        Contender(
            Result("symkin batched C via ctypes (`puma560_inverse_dynamics_batch`)", ours=True),
            UNPACK + f"tau = empty(({BATCH}, 6)); c_id_batch({BATCH}, x.ctypes.data, "
            "v.ctypes.data, a.ctypes.data, P_ptr, tau.ctypes.data)",
        ),
        Contender(
            Result("symkin extension, one call on the batch"),
            UNPACK + "ext.inverse_dynamics(x, v, a)",
        ),
        Contender(
            Result("symkin NumPy module (broadcasts)"), UNPACK + "np_dyn.inverse_dynamics(x, v, a)"
        ),
        Contender(
            Result("Robotics Toolbox `rne` on the whole trajectory (one C call)"),
            UNPACK + "puma.rne(x, v, a)",
        ),
    ]


# --------------------------------------------------------------------------- table


def ops_cell(runs: Runs, kernel: str) -> str:
    ops = runs.last("ops")
    return "—" if ops is None else str(ops[kernel])


def derivation_tables(runs: dict[tuple[str, str], Runs], repeat: int) -> list[str]:
    lines = [
        "### Derivation time",
        "",
        f"CPU seconds, median (min–max) of {repeat} run{'s' if repeat > 1 else ''}, each in a "
        "fresh process. *Full dynamics* is `derive` + `dynamics_kernels` (M, G, c, C, tau) "
        "and then the NumPy, C and CasADi modules (with forward dynamics); *tau alone* is the "
        "Newton–Euler recursion and its kernel; *Lagrange* is `derive(robot).lagrange` "
        "(M, C, c, G, no code).",
        "",
        "| robot | inertia | geometry | full dynamics [s] | of which derivation + kernels [s] "
        "| of which emitting [s] | tau alone [s] | Lagrange [s] |",
        "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: |",
    ]
    for robot, inertia, geometry in VARIANTS:
        name = variant_name(robot, inertia, geometry)
        full = runs["full", name]
        lines.append(
            f"| {robot} | {inertia} | {geometry} | {timing_cell(full, 'seconds')} "
            f"| {timing_cell(full, 'derive_s')} | {timing_cell(full, 'emit_s')} "
            f"| {timing_cell(runs['tau', name], 'seconds')} "
            f"| {timing_cell(runs['lagrange', name], 'seconds')} |"
        )
    lines += [
        "",
        "The issue's figures for the peers (PUMA 560 with numeric geometry and symbolic inertia "
        "unless it says Panda; SymPy 1.14 on the same kind of 2-core machine; not measured in "
        "this run):",
        "",
        "| peer | derivation time (from the issue) |",
        "| --- | --- |",
        *(f"| {peer} | {figure} |" for peer, figure in ISSUE_DERIVATION),
        "",
        "### Operations of the generated kernels",
        "",
        "Operations after CSE, as in the generated files' headers (`Kernel.operation_counts`).",
        "",
        "| robot | inertia | geometry | M | G | c = C dq | C | tau (inverse dynamics) |",
        "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: |",
    ]
    for robot, inertia, geometry in VARIANTS:
        full = runs["full", variant_name(robot, inertia, geometry)]
        cells = " | ".join(ops_cell(full, k) for k in KERNELS)
        lines.append(f"| {robot} | {inertia} | {geometry} | {cells} |")
    lines += [
        "",
        "| peer | operations (from the issue) |",
        "| --- | --- |",
        *(f"| {peer} | {figure} |" for peer, figure in ISSUE_OPERATIONS),
    ]
    return lines


def c_loop_table(
    runs: dict[tuple[str, str], Runs],
    results: dict[tuple[str, str, str], Run],
    settings: Settings,
) -> list[str]:
    operations = {
        key: ops_cell(runs["full", variant_name(*variant)], "inverse_dynamics")
        for key, (variant, _) in BUILDS.items()
    }
    return [
        "### Inverse and forward dynamics per call in a C loop",
        "",
        f"Median of {settings.c_rounds * settings.c_repeats} repeats ({settings.c_rounds} "
        f"alternated rounds of {settings.c_repeats}) of {settings.c_calls:,} calls over 65,536 "
        "states (`bench/dynamics_speed_loop.c`: q in [−π, π), dq in [−2, 2), and ddq, or tau "
        "for forward dynamics, in [−5, 5)). symkin C is the generated `<robot>_inverse_dynamics` "
        "and `<robot>_forward_dynamics`. *Parameters as input `p`* is the catalogue robot: its "
        "geometric parameters are an input array (the file's values passed at run time) of "
        "symkin's code and of CasADi's code of symkin's graph. *Numeric parameters* is the "
        "catalogue robot's `with_parameter_values()` (`symkin derive puma560 "
        "--numeric-parameters`): the numbers are folded into the code, there is no `p`, and "
        "the recursion runs on base inertial parameters. The independent CasADi model always "
        "has the numbers folded in. The Panda carries the inertial data of Gaz et al. (2019), "
        "the values of Robotics Toolbox's `models.DH.Panda`. " + METHOD + " Ratios are an "
        "implementation's median over symkin's (above 1: symkin is faster). Operations of "
        "symkin's tau kernel: "
        + ", ".join(f"{BUILDS[key][1]} {ops}" for key, ops in operations.items())
        + ".",
        "",
        *c_loop_rows(
            results,
            {key: label for key, (_, label) in BUILDS.items()},
            C_LOOP_LABELS,
        ),
    ]


def python_tables(
    rows: list[Contender], empty: Contender, batch: list[Contender], c_loop_ns: float
) -> list[str]:
    extension_ns = next(c.result.median for c in rows if c.result.ours)
    lines = [
        "### PUMA 560 inverse dynamics per call from Python",
        "",
        "Each call on a different state (from a pool of 65,536). An empty loop iteration, "
        f"included in every figure, took {ns_text(empty.result.median)} ns. Ratios are a "
        "contender's median over symkin's C in the C loop and over symkin's C called through "
        "its generated CPython extension (`python/puma560_ext.c`, built as `symkin derive` "
        "builds it).",
        "",
        "| how | tau [ns/call] | ratio to symkin C loop | ratio to symkin extension "
        "| repeats × calls |",
        "| --- | ---: | ---: | ---: | ---: |",
    ]
    for c in rows:
        value, ratio = result_cells(c.result, c_loop_ns)
        label = f"**{c.result.label}**" if c.result.ours else c.result.label
        count = f"{len(c.result.values)} × {c.batch}" if c.result.values else "—"
        lines.append(
            f"| {label} | {value} | {ratio} | {ratio_text(c.result.median, extension_ns)} "
            f"| {count} |"
        )
    reference = next(c.result.median for c in batch if c.result.ours)
    lines += [
        "",
        f"### PUMA 560 inverse dynamics in batches of {BATCH:,} states from Python",
        "",
        "| how | per state [ns] | ratio to symkin batched C | repeats |",
        "| --- | ---: | ---: | ---: |",
    ]
    for c in batch:
        label = f"**{c.result.label}**" if c.result.ours else c.result.label
        value, ratio = result_cells(c.result, reference, 1 / BATCH)
        lines.append(f"| {label} | {value} | {ratio} | {len(c.result.values)} |")
    return lines


def targets_table(
    runs: dict[tuple[str, str], Runs], c_results: dict[tuple[str, str, str], Run]
) -> list[str]:
    def ops(variant: tuple[str, str, str]) -> int | None:
        counts = runs["full", variant_name(*variant)].last("ops")
        return None if counts is None else counts["inverse_dynamics"]

    checks: list[tuple[str, str, bool | None]] = []
    for robot, limit in TARGET_DERIVATION_S.items():
        median = runs["full", variant_name(robot, "symbolic", "symbolic")].median("seconds")
        checks.append(
            (
                f"{robot}: full dynamics with symbolic inertia derived and emitted in under "
                f"{limit:g} s",
                "—" if median is None else f"{seconds_text(median)} s",
                None if median is None else median < limit,
            )
        )
    for robot, theirs in SYMPYBOTICS_OPERATIONS.items():
        for geometry in ("numeric", "symbolic"):
            ours = ops((robot, "symbolic", geometry))
            checks.append(
                (
                    f"{robot}: tau with symbolic inertia, {geometry} geometry, at most half "
                    f"SymPyBotics' {theirs} operations ({theirs // 2})",
                    "—" if ours is None else str(ours),
                    None if ours is None else ours <= theirs / 2,
                )
            )
    for key in PUMA_BUILDS:
        variant, label = BUILDS[key]
        ours = ops(variant)
        checks.append(
            (
                f"{label}: tau with the catalogue's numeric inertia under "
                f"{TARGET_NUMERIC_OPERATIONS} operations",
                "—" if ours is None else str(ours),
                None if ours is None else ours < TARGET_NUMERIC_OPERATIONS,
            )
        )
    for key in PUMA_BUILDS:
        c_ns = c_results[key, "inverse_dynamics", "symkin"].median
        checks.append(
            (
                f"{BUILDS[key][1]}: generated C inverse dynamics under {TARGET_C_NS:g} ns per "
                "call in a C loop",
                f"{ns_text(c_ns)} ns",
                c_ns < TARGET_C_NS,
            )
        )
    checks += peer_targets(c_results, {k: label for k, (_, label) in BUILDS.items()}, C_LOOP_LABELS)
    lines = ["### Targets", "", "| target | measured | |", "| --- | ---: | --- |"]
    for text, measured, met in checks:
        verdict = "not measured" if met is None else ("met" if met else "**NOT met**")
        lines.append(f"| {text} | {measured} | {verdict} |")
    return lines


def render(
    runs: dict[tuple[str, str], Runs],
    c_results: dict[tuple[str, str, str], Run],
    per_call: tuple[list[Contender], Contender],
    batch: list[Contender],
    checked: Checked,
    settings: Settings,
    repeat: int,
    cc: str,
    flags: tuple[str, ...],
    load: tuple[float, float],
    quick: bool,
) -> str:
    today = datetime.datetime.now(datetime.UTC).date().isoformat()
    packages = [
        ("NumPy", "numpy"),
        ("SymPy", "sympy"),
        ("SymEngine", "symengine"),
        ("CasADi", "casadi"),
        ("Pinocchio (`pin`)", "pin"),
        ("roboticstoolbox-python", "roboticstoolbox-python"),
        ("SymPyBotics", "sympybotics"),
    ]
    versions = ", ".join(f"{label} {version(package)}" for label, package in packages)
    c_loop_ns = c_results["puma560", "inverse_dynamics", "symkin"].median
    lines = [
        f"Measured on {today}: {cpu_model()}, {os.cpu_count()} cores; Python "
        f"{platform.python_version()}, symkin {version('symkin')}, {versions}; C compiled by "
        f"{compiler_version(cc)} with `{' '.join(flags)}`. Load average (1 min) at the start "
        f"and end of the run: {load[0]:.1f} and {load[1]:.1f}."
        + (" Quick run (`--quick`): few repeats." if quick else "")
        + " Generated by `bench/dynamics_speed.py`.",
        "",
        *derivation_tables(runs, repeat),
        "",
        *c_loop_table(runs, c_results, settings),
        "",
        *python_tables(*per_call, batch, c_loop_ns),
        "",
        f"The issue's per-call figures, for comparison (not measured in this run): "
        f"{ISSUE_PER_CALL}.",
        "",
        *targets_table(runs, c_results),
        "",
        "Before timing, every implementation's torques were compared with symkin's C at "
        f"{CHECK_STATES} random states (largest difference, N·m): "
        + ", ".join(f"{what} {worst:.1e}" for what, worst in checked.differences.items())
        + ". The C-loop checksums of symkin's and both CasADi codes agree. "
        + " ".join(checked.notes),
    ]
    return "\n".join(lines)


# --------------------------------------------------------------------------- main


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats (a few minutes)")
    parser.add_argument(
        "--rounds", type=int, help="alternated C-loop rounds (default 5; 2 with --quick)"
    )
    parser.add_argument(
        "--repeat", type=int, help="fresh processes per derivation measurement (3; quick 1)"
    )
    parser.add_argument(
        "--timeout", type=float, default=600.0, help="CPU-time limit of one derivation (600 s)"
    )
    parser.add_argument("--docs", type=Path, default=DOCS, help=f"file to update ({DOCS})")
    parser.add_argument("--no-write", action="store_true", help="print only")
    parser.add_argument("--child", nargs=3, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        _child(args.child)
        return 0
    settings = QUICK if args.quick else FULL
    if args.rounds is not None:
        if args.rounds < 1:
            parser.error("--rounds must be at least 1")
        settings = dataclasses.replace(settings, c_rounds=args.rounds)
    repeat = args.repeat or (1 if args.quick else 3)
    if repeat < 1:
        parser.error("--repeat must be at least 1")

    missing = [m for m in ("pinocchio", "roboticstoolbox") if importlib.util.find_spec(m) is None]
    if missing:
        raise SystemExit(
            f"{' and '.join(missing)} missing: install the bench extra "
            "(.venv/bin/pip install -e '.[test,bench]')"
        )
    load_start = os.getloadavg()[0]
    runs = derivations(repeat, args.timeout)
    cc, flags = compiler(), tuple(OPTIMISATION_FLAGS)
    rng = np.random.default_rng(560)
    checked = Checked()
    with tempfile.TemporaryDirectory(prefix="symkin-dynamics-speed-") as temporary:
        _progress("generating and building the inverse dynamics ...")
        builds = {key: build(Path(temporary) / key, key, cc, flags) for key in BUILDS}
        _progress("checking every implementation against symkin's C ...")
        check_numeric_parameters(builds["puma560-numeric"], builds["puma560"], rng, checked)
        check_panda(builds["panda"], rng, checked)
        for b in builds.values():
            check_casadi_dynamics(b, rng, checked)
        peers = prepare_puma(builds["puma560"], rng, checked)

        c_results = c_loop(builds, settings)

        samples = [with_addresses(tuple(state)) for state in random_states(rng, SAMPLES, 6)]
        rows, empty = per_call_contenders()
        time_contenders(
            [empty, *rows],
            samples,
            peers,
            settings.py_repeats,
            settings.py_budget_s,
            settings.py_batch_ns,
            "inverse dynamics per call",
        )
        states = random_states(rng, BATCH, 6)
        trajectory = with_addresses(tuple(states[:, k] for k in range(3)))
        batch = batch_contenders()
        time_contenders(
            batch,
            [trajectory],
            peers,
            settings.batch_repeats,
            settings.batch_budget_s,
            None,
            "inverse dynamics batch",
        )
    table = render(
        runs,
        c_results,
        (rows, empty),
        batch,
        checked,
        settings,
        repeat,
        cc,
        flags,
        (load_start, os.getloadavg()[0]),
        args.quick,
    )
    print(table)
    if not args.no_write:
        write_docs(table, args.docs, (BEGIN, END), "Dynamics")
        _progress(f"wrote {args.docs}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
