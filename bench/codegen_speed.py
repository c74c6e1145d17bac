"""Speed of symkin's generated PUMA 560 code against other ways to compute the same kinematics.

The script generates every backend of the catalogue PUMA 560 into a temporary directory and
builds the CPython extension (as ``symkin derive puma560 --out DIR`` does), then times, in
one run and on the same machine:

* **C loop.** ``bench/codegen_speed_loop.c`` calls ``<robot>_fk`` and ``<robot>_fk_jacobian``
  of the PUMA 560 and the Panda over a table of 65,536 joint vectors, timed with
  ``clock_gettime`` inside C; the same harness calls the C that ``casadi.CodeGenerator`` writes
  for the generated CasADi module's ``fk_function()`` and ``fk_jacobian_function()`` (CasADi
  printing symkin's graph) and for the independent CasADi model of ``bench/casadi_peer.py``
  (written from the DH table).  All are compiled with the flags symkin builds its extension
  with (``gcc -O2``), the kernels in their own translation unit, and alternated round by round
  (``bench/c_loop.py``); each harness run reports its peak resident set.
* **Per call from Python.** symkin's extension (``fk(q)``, ``jacobian(q)``), ctypes on the
  same C, ctypes on CasADi's C, a ``casadi.Function`` call, Pinocchio
  (``framesForwardKinematics``, ``computeFrameJacobian``) on a model built from the same DH
  table, SymPy ``lambdify`` (``cse=True``) and Robotics Toolbox (``fkine``, ``jacob0``).
* **Batch FK of 100,000 configurations.** The extension's batched C entry point, the generated
  NumPy module, SymEngine's LLVM ``Lambdify``, SymPy ``lambdify`` on arrays and Robotics
  Toolbox.
* **Operations after CSE** of FK + Jacobian: symkin's ``fk_jacobian`` kernel against Robotics
  Toolbox's symbolic ``fkine`` + ``jacob0`` passed through ``sympy.cse``.

Every peer's result is checked against symkin's at random joint angles before it is timed
(the script stops if one disagrees).  Times are medians of many short repeats on the CPU-time
clock of the timing thread (``CLOCK_THREAD_CPUTIME_ID``, in C and in Python), which does not
count the time other programs on the shared machine hold the CPU; the contenders are
interleaved repeat by repeat so that what load still shows (caches, a busy sibling core)
falls on all of them alike.  The load average at the start and end is recorded with the
table.  No test passes or fails on these numbers.

The script prints a Markdown table and writes it into ``docs/benchmarks.md`` between
``<!-- codegen-speed:begin -->`` and ``<!-- codegen-speed:end -->``.

Usage::

    .venv/bin/python bench/codegen_speed.py            # full run, about 2 CPU minutes
    .venv/bin/python bench/codegen_speed.py --quick    # fewer repeats, under 1 minute
    .venv/bin/python bench/codegen_speed.py --quick --no-write
"""

from __future__ import annotations

import argparse
import ctypes
import dataclasses
import datetime
import gc
import importlib.util
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from importlib import metadata
from pathlib import Path
from types import ModuleType

import numpy as np

from c_loop import METHOD, Job, Run, casadi_c, compile_harness, peer_targets, run_rounds
from c_loop import table as c_loop_table

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs" / "benchmarks.md"
BEGIN = "<!-- codegen-speed:begin -->"
END = "<!-- codegen-speed:end -->"
HARNESS = Path(__file__).resolve().with_name("codegen_speed_loop.c")
ROBOT = "puma560"
C_LOOP_ROBOTS = {"puma560": "PUMA 560", "panda": "Panda"}
C_LOOP_KERNELS = ("fk", "fk_jacobian")
C_LOOP_LABELS = {"fk": "FK", "fk_jacobian": "FK + Jacobian"}
BATCH = 100_000  # configurations in the batch measurements
SAMPLES = 65_536  # distinct joint vectors the per-call measurements walk through
MIN_REPEATS = 3  # a contender that runs past its time budget still gets this many repeats
TOLERANCE = 1e-12  # largest difference allowed between a peer's result and symkin's
# The clock of every Python timing: CPU time of this thread, in ns (CLOCK_THREAD_CPUTIME_ID,
# as in the C harness).  On the shared 2-core machine, wall time counts the slices other
# programs get; CPU time does not.  The timed code is single-threaded (the extension releases
# the GIL but computes in the calling thread).
CLOCK = time.thread_time_ns

# The targets.
TARGET_C_FK_JACOBIAN_NS = 150.0
TARGET_BATCH_C_PER_S = 5e6
TARGET_BATCH_NUMPY_PER_S = 1.5e6
TARGET_OPERATIONS = 367


@dataclass(frozen=True)
class Settings:
    c_rounds: int  # harness processes per implementation and kernel, interleaved
    c_repeats: int  # timed repeats inside one harness process
    c_calls: int  # calls per repeat in C
    py_repeats: int  # repeats of every per-call contender
    py_budget_s: float  # CPU seconds after which a per-call contender stops repeating
    py_batch_ns: float  # aim for per-call batches of about this long (capped at SAMPLES calls)
    batch_repeats: int
    batch_budget_s: float


FULL = Settings(
    c_rounds=5,
    c_repeats=9,
    c_calls=200_000,
    py_repeats=51,
    py_budget_s=10.0,
    py_batch_ns=5e6,
    batch_repeats=11,
    batch_budget_s=30.0,
)
QUICK = Settings(
    c_rounds=2,
    c_repeats=5,
    c_calls=100_000,
    py_repeats=11,
    py_budget_s=2.0,
    py_batch_ns=2e6,
    batch_repeats=3,
    batch_budget_s=10.0,
)


def _progress(text: str) -> None:
    print(text, file=sys.stderr, flush=True)


# --------------------------------------------------------------------------- results


@dataclass
class Result:
    """The repeats of one contender: nanoseconds per call (or per batch)."""

    label: str
    values: list[float] = field(default_factory=list)
    error: str | None = None
    ours: bool = False

    @property
    def median(self) -> float | None:
        return statistics.median(self.values) if self.values else None


class CheckError(RuntimeError):
    """A peer's result differs from symkin's: timing it would compare different things."""


def check_close(what: str, actual, expected, tolerance: float = TOLERANCE) -> float:
    actual = np.asarray(actual, dtype=float)
    expected = np.asarray(expected, dtype=float)
    if actual.shape != expected.shape:
        raise CheckError(f"{what}: shape {actual.shape}, expected {expected.shape}")
    worst = float(np.abs(actual - expected).max())
    if not worst <= tolerance:
        raise CheckError(f"{what}: differs from symkin by {worst:.3g} (> {tolerance:g})")
    return worst


# --------------------------------------------------------------------------- building


def compiler() -> str:
    found = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc")
    if found is None:
        raise SystemExit("no C compiler found (looked for $CC, cc, gcc)")
    return found


def compiler_version(cc: str) -> str:
    done = subprocess.run([cc, "--version"], capture_output=True, text=True, check=False)
    return (done.stdout.splitlines() or [cc])[0]


def compile_c(cc: str, flags: tuple[str, ...], sources: list[Path], output: Path, *extra: str):
    command = [cc, *flags, *extra, *map(str, sources), "-o", str(output), "-lm"]
    done = subprocess.run(command, capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise SystemExit(f"compiling {output.name} failed:\n{done.stderr}")
    return output


@dataclass(frozen=True)
class Libraries:
    """symkin's C and CasADi's C of the same kernels as shared libraries (for ctypes)."""

    ours: Path
    casadi: Path


def shared_libraries(cc: str, flags: tuple[str, ...], directory: Path, name: str) -> Libraries:
    """``c/<name>.c`` and ``casadi_c/casadi_<name>.c`` compiled as shared libraries."""
    shared = ("-shared", "-fPIC")
    return Libraries(
        ours=compile_c(
            cc, flags, [directory / "c" / f"{name}.c"], directory / "libsymkin.so", *shared
        ),
        casadi=compile_c(
            cc, flags, [directory / "casadi_c" / f"casadi_{name}.c"], directory / "libcasadi.so",
            *shared,
        ),
    )  # fmt: skip


def load_module(path: Path) -> ModuleType:
    spec = importlib.util.spec_from_file_location(path.stem, path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@dataclass
class Build:
    """symkin's generated PUMA 560 code, built, plus CasADi's C for the same kernels."""

    directory: Path
    ext: ModuleType  # the CPython extension
    numpy_module: ModuleType
    casadi_module: ModuleType
    kernels: dict  # name -> symkin.kernels.Kernel
    model: object  # symkin.derive.Model
    robot: object  # symkin.robot.Robot
    parameters: np.ndarray  # default parameter values, file order
    flags: tuple[str, ...]
    cc: str
    lib_ours: Path
    lib_casadi: Path


def build(directory: Path) -> Build:
    from symkin import derive, load_robot
    from symkin.generate import files_for_robot
    from symkin.kernels import kinematics_kernels
    from symkin.output_folder import write_folder
    from symkin.runtime.extension import OPTIMISATION_FLAGS, build_extension, load_extension

    robot = load_robot(ROBOT)
    write_folder(directory, files_for_robot(robot))
    ext = load_extension(
        build_extension(directory / "python" / f"{ROBOT}_ext.c", directory / "c" / f"{ROBOT}.c")
    )
    numpy_module = load_module(directory / "numpy" / f"{ROBOT}_kinematics.py")
    casadi_module = load_module(directory / "casadi" / f"{ROBOT}_casadi.py")
    model = derive(robot)
    kernels = {k.name: k for k in kinematics_kernels(model)}

    # CasADi's C code for the generated CasADi module's FK (ctypes from Python).
    casadi_c([casadi_module.fk_function()], directory / "casadi_c", f"casadi_{ROBOT}")
    cc = compiler()
    flags = tuple(OPTIMISATION_FLAGS)
    built = shared_libraries(cc, flags, directory, ROBOT)
    return Build(
        directory=directory,
        ext=ext,
        numpy_module=numpy_module,
        casadi_module=casadi_module,
        kernels=kernels,
        model=model,
        robot=robot,
        parameters=np.array(list(robot.parameter_values().values()), dtype=float),
        flags=flags,
        cc=cc,
        lib_ours=built.ours,
        lib_casadi=built.casadi,
    )


# --------------------------------------------------------------------------- C loop


def kinematics_loops(directory: Path, cc: str, flags: tuple[str, ...]) -> list[Job]:
    """The C-loop jobs of FK and FK + Jacobian for every robot of ``C_LOOP_ROBOTS``: symkin's
    generated C, CasADi's C of the generated CasADi module, CasADi's C of the independent model
    (each checked against symkin's NumPy module at random joint vectors first)."""
    import casadi_peer
    from symkin import load_robot
    from symkin.generate import files_for_robot
    from symkin.output_folder import write_folder

    jobs = []
    for name in C_LOOP_ROBOTS:
        robot, folder = load_robot(name), directory / f"loop_{name}"
        write_folder(folder, files_for_robot(robot, ("numpy", "c", "casadi"), dynamics=False))
        graph = load_module(folder / "casadi" / f"{name}_casadi.py")
        graph_functions = [graph.fk_function(), graph.fk_jacobian_function()]
        peer_functions = casadi_peer.functions(robot, C_LOOP_KERNELS)
        check_kinematics(robot, load_module(folder / "numpy" / f"{name}_kinematics.py"),
                         {"graph": graph_functions, "peer": peer_functions})  # fmt: skip
        sources = {
            "symkin": folder / "c" / f"{name}.c",
            "graph": casadi_c(graph_functions, folder / "casadi_c", f"casadi_{name}"),
            "peer": casadi_c(peer_functions, folder / "peer_c", f"peer_{name}"),
        }
        n_p = len(robot.parameters)
        defines = (f"-DROBOT={name}", f"-DDOF={robot.dof}", f"-DN_P={n_p}")
        parameters = [repr(float(v)) for v in robot.parameter_values().values()]
        for impl, source in sources.items():
            output = folder / f"loop_{impl}"
            executable = compile_harness(cc, flags, HARNESS, source, output, *defines)
            for kernel in C_LOOP_KERNELS:
                jobs.append(Job(name, kernel, impl, (str(executable), kernel, "{calls}",
                                                     "{repeats}", *parameters)))  # fmt: skip
    return jobs


def check_kinematics(robot, numpy_module, functions: dict[str, list]) -> None:
    """Every CasADi function's T and J against symkin's NumPy module at 20 joint vectors."""
    rng = np.random.default_rng(7)
    P = np.array(list(robot.parameter_values().values()), dtype=float)
    for q in rng.uniform(-np.pi, np.pi, (20, robot.dof)):
        T, J = numpy_module.fk_jacobian(q, P)
        for impl, (fk, fk_jacobian) in functions.items():
            check_close(f"{robot.name} {impl} fk", fk(q, P).full(), T)
            T2, J2 = fk_jacobian(q, P)
            check_close(f"{robot.name} {impl} fk_jacobian (T)", T2.full(), T)
            check_close(f"{robot.name} {impl} fk_jacobian (J)", J2.full(), J)


def c_loop(jobs: list[Job], settings: Settings) -> dict[tuple[str, str, str], Run]:
    """ns per call in a C loop of every job, alternated round by round."""
    fill = {"{calls}": str(settings.c_calls), "{repeats}": str(settings.c_repeats)}
    jobs = [replace(j, command=tuple(fill.get(c, c) for c in j.command)) for j in jobs]
    return run_rounds(jobs, settings.c_rounds)


# --------------------------------------------------------------------------- peers


def standard_dh_constant(joint, value: Callable) -> np.ndarray:
    """``Rz(theta) Tz(d) Tx(a) Rx(alpha)`` of one standard DH row, numerically."""
    theta, d, a, alpha = (value(getattr(joint, key)) for key in ("theta", "d", "a", "alpha"))
    ct, st, ca, sa = np.cos(theta), np.sin(theta), np.cos(alpha), np.sin(alpha)
    return np.array(
        [
            [ct, -st * ca, st * sa, a * ct],
            [st, ct * ca, -ct * sa, a * st],
            [0.0, sa, ca, d],
            [0.0, 0.0, 0.0, 1.0],
        ]
    )


def casadi_c_function(library: Path, name: str):
    """``name`` from C written by ``casadi.CodeGenerator``, through ctypes: its signature
    ``(arg, res, iw, w, mem)``; it must need no work arrays (true of SX functions), so the
    callers pass NULL for ``iw`` and ``w``."""
    lib = ctypes.CDLL(str(library))
    function = lib[name]
    function.argtypes = [
        ctypes.POINTER(ctypes.c_void_p),
        ctypes.POINTER(ctypes.c_void_p),
        ctypes.c_void_p,
        ctypes.c_void_p,
        ctypes.c_int,
    ]
    function.restype = ctypes.c_int
    sizes = [ctypes.c_longlong() for _ in range(4)]  # sz_arg, sz_res, sz_iw, sz_w
    lib[f"{name}_work"](*(ctypes.byref(s) for s in sizes))
    if sizes[2].value or sizes[3].value:
        raise CheckError(f"CasADi {name} needs work arrays {[s.value for s in sizes]}")
    return function


def pinocchio_model(robot, parameter_values: dict[str, float]):
    """A Pinocchio model of the same standard DH table, and the id of its tool frame.

    ``T = base * Rz(q1) C1 * Rz(q2) C2 * ... * Rz(qn) Cn * tool`` with ``C_i`` the constant
    part ``Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)`` of row i.  Joint i is a revolute joint
    about z placed at ``C_{i-1}`` in joint i-1's frame (``base`` for joint 1); the tool frame
    hangs off the last joint at ``Cn * tool``.
    """
    import pinocchio as pin

    def value(expr) -> float:
        return float(expr.subs({s: parameter_values[s.name] for s in expr.free_symbols}))

    if robot.convention != "standard" or any(j.type != "revolute" for j in robot.joints):
        raise ValueError("this model builder handles standard DH, revolute joints only")
    model = pin.Model()
    parent = 0
    placement = np.array(robot.base.applyfunc(value).tolist(), dtype=float)
    for i, joint in enumerate(robot.joints, start=1):
        parent = model.addJoint(parent, pin.JointModelRZ(), pin.SE3(placement), f"joint{i}")
        placement = standard_dh_constant(joint, value)
    tool = placement @ np.array(robot.tool.applyfunc(value).tolist(), dtype=float)
    frame = model.addFrame(pin.Frame("tool", parent, pin.SE3(tool), pin.FrameType.OP_FRAME))
    return model, frame


def _import_error(error: Exception) -> str:
    if isinstance(error, ModuleNotFoundError):
        return "not installed"
    return f"not importable ({type(error).__name__})"


@dataclass
class Peers:
    """Everything the Python-side statements refer to, with the reason a peer is missing."""

    namespace: dict
    missing: dict[str, str] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)


def prepare_peers(b: Build, rng: np.random.Generator) -> Peers:
    """Build every peer and check its results against symkin's at random joint angles."""
    import sympy

    ns: dict = {"np": np, "empty": np.empty, "ext": b.ext, "np_kin": b.numpy_module}
    peers = Peers(ns)
    P = b.parameters
    ns["P"] = P
    qs = rng.uniform(-np.pi, np.pi, (20, 6))
    expected_T = b.ext.fk(qs)
    expected_J = b.ext.jacobian(qs)
    check_close("symkin NumPy module fk", b.numpy_module.fk(qs), expected_T)
    T2, J2 = b.ext.fk_jacobian(qs)
    check_close("symkin extension fk_jacobian (T)", T2, expected_T)
    check_close("symkin extension fk_jacobian (J)", J2, expected_J)

    # ctypes on symkin's C.
    lib = ctypes.CDLL(str(b.lib_ours))
    c_fk = lib[f"{ROBOT}_fk"]
    c_fk.argtypes = [ctypes.c_void_p] * 3
    c_fk.restype = None
    ns.update(c_fk=c_fk, P_ptr=P.ctypes.data)
    for q, T in zip(qs, expected_T, strict=True):
        out = np.empty((4, 4))
        c_fk(q.ctypes.data, P.ctypes.data, out.ctypes.data)
        check_close("ctypes on symkin's C", out, T)

    # CasADi: the generated module's Function, and its generated C through ctypes.
    f_fk = b.casadi_module.fk_function()
    ns["casadi_fk"] = f_fk
    if f_fk.sparsity_out(0).nnz() != 16:
        raise CheckError("CasADi fk output is not a dense 4x4")
    cas_fk = casadi_c_function(b.lib_casadi, f"{ROBOT}_fk")
    ns.update(
        cas_fk=cas_fk,
        cas_arg=(ctypes.c_void_p * 2)(None, P.ctypes.data),
        cas_res=(ctypes.c_void_p * 1)(),
    )
    for q, T in zip(qs, expected_T, strict=True):
        check_close("casadi.Function fk", f_fk(q, P).full(), T)
        out = np.empty((4, 4), order="F")  # CasADi writes column-major
        ns["cas_arg"][0] = q.ctypes.data
        ns["cas_res"][0] = out.ctypes.data
        cas_fk(ns["cas_arg"], ns["cas_res"], None, None, 0)
        check_close("ctypes on CasADi's C", out, T)

    # SymPy lambdify (cse=True) of symkin's own simplified FK, parameters as numbers.
    robot, model = b.robot, b.model
    values = dict(zip(robot.parameter_symbols, P.tolist(), strict=True))
    T_sym = model.forward_kinematics.subs(values)
    q_sym = list(model.q)
    sympy_fk = sympy.lambdify([q_sym], T_sym, modules="numpy", cse=True)
    top = [(i, j) for i in range(3) for j in range(4)]
    sympy_top = sympy.lambdify([q_sym], [T_sym[i, j] for i, j in top], modules="numpy", cse=True)

    def sympy_fk_batch(Q):
        """SymPy's lambdify on arrays, assembled into (N, 4, 4) like symkin's output."""
        entries = sympy_top(Q.T)
        T = np.empty((Q.shape[0], 4, 4))
        for (i, j), entry in zip(top, entries, strict=True):
            T[:, i, j] = entry
        T[:, 3, :] = (0.0, 0.0, 0.0, 1.0)
        return T

    ns.update(sympy_fk=sympy_fk, sympy_fk_batch=sympy_fk_batch)
    check_close("SymPy lambdify (batch)", sympy_fk_batch(qs), expected_T)
    for q, T in zip(qs, expected_T, strict=True):
        check_close("SymPy lambdify", sympy_fk(q), T)

    # SymEngine's LLVM Lambdify of the same expression.
    try:
        import symengine
    except Exception as error:
        peers.missing["symengine"] = _import_error(error)
    else:
        if not getattr(symengine, "have_llvm", False):
            peers.missing["symengine"] = "SymEngine is built without LLVM support"
        else:
            se_fk = symengine.Lambdify(
                [symengine.sympify(s) for s in q_sym],
                symengine.Matrix(T_sym.tolist()),
                backend="llvm",
                cse=True,
            )
            ns["se_fk"] = se_fk
            check_close("SymEngine LLVM Lambdify", se_fk(qs), expected_T)

    # Pinocchio, on a model built from the same DH table.
    try:
        import pinocchio as pin
    except Exception as error:
        peers.missing["pinocchio"] = _import_error(error)
    else:
        pin_model, frame = pinocchio_model(robot, robot.parameter_values())
        data = pin_model.createData()
        lwa = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
        ns.update(pin=pin, model=pin_model, data=data, fid=frame, LWA=lwa)
        for q, T, J in zip(qs, expected_T, expected_J, strict=True):
            pin.framesForwardKinematics(pin_model, data, q)
            check_close("Pinocchio framesForwardKinematics", data.oMf[frame].homogeneous, T)
            jac = pin.computeFrameJacobian(pin_model, data, q, frame, lwa)
            check_close("Pinocchio computeFrameJacobian (LOCAL_WORLD_ALIGNED)", jac, J)

    # Robotics Toolbox: its DH model of the same arm, and the ETS (C extension) of it.
    try:
        import roboticstoolbox as rtb
    except Exception as error:
        peers.missing["rtb"] = _import_error(error)
    else:
        puma = rtb.models.DH.Puma560()
        ets = puma.ets()
        ns.update(puma=puma, ets=ets)
        # RTB's PUMA stands on a pedestal, d1 = 0.672 m: T_rtb = Tz(d1) T_symkin (Rz(q1) and
        # Tz(d1) commute).  Nothing else differs, and the Jacobian does not see the pedestal.
        pedestal = float(puma.links[0].d)
        shifted = expected_T.copy()
        shifted[:, 2, 3] += pedestal
        for q, T, J in zip(qs, shifted, expected_J, strict=True):
            check_close("RTB DH fkine (pedestal added to symkin's z)", puma.fkine(q).A, T)
            check_close("RTB ETS eval", ets.eval(q), T)
            check_close("RTB DH jacob0", puma.jacob0(q), J)
            check_close("RTB ETS jacob0", ets.jacob0(q), J)
        check_close("RTB DH fkine (batch)", np.asarray(puma.fkine(qs).A), shifted)
        check_close("RTB ETS eval (batch)", ets.eval(qs), shifted)
        peers.notes.append(
            f"Robotics Toolbox's `DH.Puma560()` is the same DH table with a {pedestal:.4g} m "
            "pedestal as d1; its poses are checked against symkin's with the pedestal added "
            "to z."
        )
    return peers


# --------------------------------------------------------------------------- Python timing


@dataclass
class Contender:
    result: Result
    statement: str
    needs: str | None = None  # key of Peers.missing that disables it
    loop: Callable | None = None
    batch: int = 1
    spent_ns: float = 0.0


def compile_loop(statement: str, namespace: dict) -> Callable:
    """``for q in qs: <statement>`` as a function, the statement written inline.

    Each contender's call is timed as a user would write it, with no wrapper function around
    it; the loop and the name look-ups cost the same for all.
    """
    source = (
        "def _bench_loop(_qs, _clock):\n"
        "    _start = _clock()\n"
        "    for q in _qs:\n"
        f"        {statement}\n"
        "    return _clock() - _start\n"
    )
    scope = dict(namespace)
    exec(compile(source, "<codegen_speed>", "exec"), scope)
    return scope["_bench_loop"]


def time_contenders(
    contenders: list[Contender],
    inputs: list,
    peers: Peers,
    repeats: int,
    budget_s: float,
    batch_ns: float | None,
    title: str,
) -> None:
    """Median ns per loop iteration of every contender, interleaved repeat by repeat.

    With ``batch_ns`` (per-call timings), each repeat runs a contender over as many of
    ``inputs`` as fit in about ``batch_ns`` (at least 10, at most all), each repeat on the
    next stretch of ``inputs``; without it, each repeat is one iteration over ``inputs[0]``
    (the batch measurements).
    """
    clock = CLOCK
    active = []
    for c in contenders:
        if c.needs in peers.missing:
            c.result.error = peers.missing[c.needs]
            continue
        c.loop = compile_loop(c.statement, peers.namespace)
        try:
            if batch_ns is None:
                c.loop(inputs[:1], clock)  # warm-up
                c.batch = 1
            else:
                c.loop(inputs[:10], clock)  # warm-up
                per_call = min(c.loop(inputs[:10], clock) for _ in range(3)) / 10
                c.batch = int(min(len(inputs), max(10, batch_ns / max(per_call, 1.0))))
        except Exception as error:
            c.result.error = f"failed ({type(error).__name__}: {error})"
            continue
        active.append(c)
    gc.collect()
    gc.disable()
    try:
        for r in range(repeats):
            for c in active:
                if len(c.result.values) >= MIN_REPEATS and c.spent_ns > budget_s * 1e9:
                    continue
                start = (r * c.batch) % (len(inputs) - c.batch + 1)
                elapsed = c.loop(inputs[start : start + c.batch], clock)
                c.spent_ns += elapsed
                c.result.values.append(elapsed / c.batch)
            if (r + 1) % max(1, repeats // 4) == 0 or r + 1 == repeats:
                _progress(f"{title}: repeat {r + 1}/{repeats}")
    finally:
        gc.enable()


def per_call_contenders() -> tuple[list[Contender], list[Contender], Contender]:
    fk = [
        Contender(Result("symkin CPython extension `ext.fk(q)`", ours=True), "ext.fk(q)"),
        Contender(Result("symkin NumPy module `fk(q)`"), "np_kin.fk(q)"),
        Contender(
            Result("ctypes on symkin's C (`puma560_fk`, fresh 4×4 output array)"),
            "T = empty((4, 4)); c_fk(q.ctypes.data, P_ptr, T.ctypes.data)",
        ),
        Contender(
            Result("ctypes on CasADi C of symkin's graph (fresh 4×4 output array)"),
            "T = empty((4, 4), order='F'); cas_arg[0] = q.ctypes.data; "
            "cas_res[0] = T.ctypes.data; cas_fk(cas_arg, cas_res, None, None, 0)",
        ),
        Contender(
            Result("CasADi `Function` of symkin's graph, `f(q, p).full()`"),
            "casadi_fk(q, P).full()",
        ),
        Contender(
            Result("Pinocchio `framesForwardKinematics` (pose left in `data.oMf`)"),
            "pin.framesForwardKinematics(model, data, q)",
            "pinocchio",
        ),
        Contender(
            Result("Pinocchio `framesForwardKinematics` + pose copied to NumPy"),
            "pin.framesForwardKinematics(model, data, q); T = data.oMf[fid].homogeneous",
            "pinocchio",
        ),
        Contender(
            Result(
                "Pinocchio `forwardKinematics` + `updateFramePlacement(...).homogeneous` "
                "(fastest copy-out found)"
            ),
            "pin.forwardKinematics(model, data, q); "
            "T = pin.updateFramePlacement(model, data, fid).homogeneous",
            "pinocchio",
        ),
        Contender(Result("SymPy `lambdify(..., cse=True)`"), "sympy_fk(q)"),
        Contender(Result("Robotics Toolbox `DH.Puma560().fkine(q)` (SE3)"), "puma.fkine(q)", "rtb"),
        Contender(
            Result("Robotics Toolbox ETS `ets.eval(q)` (C extension, ndarray)"),
            "ets.eval(q)",
            "rtb",
        ),
    ]
    jacobian = [
        Contender(
            Result("symkin CPython extension `ext.jacobian(q)`", ours=True), "ext.jacobian(q)"
        ),
        Contender(
            Result("symkin CPython extension `ext.fk_jacobian(q)` (T and J)"), "ext.fk_jacobian(q)"
        ),
        Contender(
            Result("Pinocchio `computeFrameJacobian(..., LOCAL_WORLD_ALIGNED)`"),
            "pin.computeFrameJacobian(model, data, q, fid, LWA)",
            "pinocchio",
        ),
        Contender(Result("Robotics Toolbox `DH.Puma560().jacob0(q)`"), "puma.jacob0(q)", "rtb"),
        Contender(
            Result("Robotics Toolbox ETS `ets.jacob0(q)` (C extension)"), "ets.jacob0(q)", "rtb"
        ),
    ]
    empty = Contender(Result("empty loop iteration"), "pass")
    return fk, jacobian, empty


def batch_contenders() -> list[Contender]:
    return [
        Contender(
            Result("symkin batched C entry point via the extension `ext.fk(Q)`", ours=True),
            "ext.fk(q)",
        ),
        Contender(Result("symkin extension `ext.fk_jacobian(Q)` (T and J)"), "ext.fk_jacobian(q)"),
        Contender(Result("symkin NumPy module `fk(Q)`"), "np_kin.fk(q)"),
        Contender(Result("SymEngine LLVM `Lambdify(..., cse=True)`"), "se_fk(q)", "symengine"),
        Contender(
            Result("SymPy `lambdify(..., cse=True)` on arrays, assembled to (N, 4, 4)"),
            "sympy_fk_batch(q)",
        ),
        Contender(Result("Robotics Toolbox ETS `ets.eval(Q)` (C extension)"), "ets.eval(q)", "rtb"),
        Contender(
            Result("Robotics Toolbox `DH.Puma560().fkine(Q)` (its own batch, SE3)"),
            "puma.fkine(q)",
            "rtb",
        ),
    ]


# --------------------------------------------------------------------------- operations


def operation_counts(b: Build) -> dict:
    """symkin's kernels' operation counts and RTB's symbolic FK + Jacobian after ``cse``."""
    result = {
        "fk_jacobian": b.kernels["fk_jacobian"].operation_counts,
        "fk": b.kernels["fk"].operation_counts,
        "jacobian": b.kernels["jacobian"].operation_counts,
    }
    try:
        import roboticstoolbox as rtb
        import spatialmath.base.symbolic as sym
        import sympy

        from symkin.kernels import count_operations
    except Exception as error:
        result["rtb_error"] = _import_error(error)
        return result
    robot = rtb.models.DH.Puma560(symbolic=True)
    q = sym.symbol(f"q1:{robot.n + 1}")
    entries = [sympy.sympify(e) for e in [*robot.fkine(q).A.flat, *robot.jacob0(q).flat]]
    assignments, reduced = sympy.cse(entries)
    result["rtb_raw"] = int(sympy.count_ops(entries))
    result["rtb_cse"] = count_operations([e for _, e in assignments] + list(reduced))
    return result


# --------------------------------------------------------------------------- table


def cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def version(package: str) -> str:
    try:
        return metadata.version(package)
    except metadata.PackageNotFoundError:
        return "not installed"


def ns_text(value: float) -> str:
    if value < 100:
        return f"{value:.1f}"
    return f"{value:,.0f}"


def ratio_text(value: float | None, reference: float | None) -> str:
    if value is None or reference is None or reference <= 0:
        return "—"
    ratio = value / reference
    if ratio < 10:
        return f"{ratio:.2f}×"
    return f"{ratio:.0f}×" if ratio >= 100 else f"{ratio:.1f}×"


def result_cells(result: Result, reference: float | None, scale: float = 1.0) -> tuple[str, str]:
    if result.error is not None:
        return result.error, "—"
    if result.median is None:
        return "—", "—"
    return ns_text(result.median * scale), ratio_text(result.median, reference)


def per_call_table(rows: list[Contender], unit: str) -> list[str]:
    reference = next(c.result.median for c in rows if c.result.ours)
    lines = [
        f"| how | {unit} [ns/call] | ratio to symkin | repeats × calls |",
        "| --- | ---: | ---: | ---: |",
    ]
    for c in rows:
        value, ratio = result_cells(c.result, reference)
        label = f"**{c.result.label}**" if c.result.ours else c.result.label
        count = f"{len(c.result.values)} × {c.batch}" if c.result.values else "—"
        lines.append(f"| {label} | {value} | {ratio} | {count} |")
    return lines


def render(
    b: Build,
    c_results: dict[tuple[str, str, str], Run],
    fk: list[Contender],
    jacobian: list[Contender],
    empty: Contender,
    batch: list[Contender],
    ops: dict,
    peers: Peers,
    settings: Settings,
    quick: bool,
    load: tuple[float, float],
) -> str:
    today = datetime.datetime.now(datetime.UTC).date().isoformat()
    llvm = peers.missing.get("symengine", "with LLVM")
    lines = [
        f"Measured on {today}: {cpu_model()}, {os.cpu_count()} cores; Python "
        f"{platform.python_version()}, NumPy {version('numpy')}, SymPy {version('sympy')}, "
        f"symkin {version('symkin')}, CasADi {version('casadi')}, Pinocchio (`pin`) "
        f"{version('pin')}, SymEngine {version('symengine')} ({llvm}), roboticstoolbox-python "
        f"{version('roboticstoolbox-python')}; C compiled by {compiler_version(b.cc)} with "
        f"`{' '.join(b.flags)}`. Medians of thread CPU time, contenders interleaved"
        f"{' (`--quick` run: fewer repeats)' if quick else ''}. Load average (1 min) at the "
        f"start and end of the run: {load[0]:.1f} and {load[1]:.1f}. "
        "Generated by `bench/codegen_speed.py`.",
        "",
        "### FK and FK + Jacobian per call inside a C loop",
        "",
        f"Median of {settings.c_rounds * settings.c_repeats} repeats ({settings.c_rounds} "
        f"alternated rounds of {settings.c_repeats}) of {settings.c_calls:,} calls over 65,536 "
        "joint vectors (`bench/codegen_speed_loop.c`). The geometric parameters are the input "
        "`p` of symkin's code and of CasADi's code of symkin's graph; the independent model has "
        "them as numbers. " + METHOD + " Ratios are an implementation's median over symkin's "
        "(above 1: symkin is faster).",
        "",
        *c_loop_table(c_results, C_LOOP_ROBOTS, C_LOOP_LABELS),
    ]
    ref_fkj = c_results[ROBOT, "fk_jacobian", "symkin"].median
    lines += [
        "",
        "### FK per call from Python",
        "",
        f"One 4×4 pose per call, each call on a different joint vector (from a pool of "
        f"{SAMPLES:,}). An empty loop iteration, included in every figure, took "
        f"{ns_text(empty.result.median)} ns. The ratio is a contender's median over "
        "symkin's (how many times longer it takes), here and below.",
        "",
        *per_call_table(fk, "FK"),
        "",
        "### Geometric Jacobian per call from Python",
        "",
        *per_call_table(jacobian, "Jacobian"),
        "",
        f"### Batch FK, {BATCH:,} configurations",
        "",
        "| how | time [ms] | configurations/s | ratio to symkin | repeats |",
        "| --- | ---: | ---: | ---: | ---: |",
    ]
    ref_batch = next(c.result.median for c in batch if c.result.ours)
    for c in batch:
        label = f"**{c.result.label}**" if c.result.ours else c.result.label
        if c.result.error is not None:
            lines.append(f"| {label} | {c.result.error} | — | — | — |")
            continue
        median = c.result.median
        rate = BATCH / (median * 1e-9)
        lines.append(
            f"| {label} | {median * 1e-6:,.1f} | {rate / 1e6:.2f} M "
            f"| {ratio_text(median, ref_batch)} | {len(c.result.values)} |"
        )

    def kinds(counts: dict) -> str:
        parts = [
            f"{counts[k]} {k}"
            for k in ("additions", "multiplications", "divisions", "trig", "sqrt", "powers")
            if counts.get(k)
        ]
        return ", ".join(parts)

    ours_ops = ops["fk_jacobian"]
    lines += [
        "",
        "### FK + Jacobian operations after CSE",
        "",
        "| how | operations | by kind |",
        "| --- | ---: | --- |",
        f"| **symkin `fk_jacobian` kernel** (`Kernel.operation_counts`) | "
        f"{ours_ops['total']} | {kinds(ours_ops)} |",
    ]
    if "rtb_cse" in ops:
        rtb_ops = ops["rtb_cse"]
        lines.append(
            "| Robotics Toolbox `DH.Puma560(symbolic=True)` `fkine` + `jacob0`, then "
            f"`sympy.cse` | {rtb_ops['total']} | {kinds(rtb_ops)} "
            f"(before CSE: {ops['rtb_raw']}) |"
        )
    else:
        lines.append(f"| Robotics Toolbox | {ops['rtb_error']} | — |")
    lines.append(
        f"| symkin `fk` kernel alone, `jacobian` kernel alone | {ops['fk']['total']}, "
        f"{ops['jacobian']['total']} | |"
    )

    # Targets.
    c_fkj = ref_fkj
    batch_c = BATCH / (ref_batch * 1e-9)
    numpy_batch = next(c for c in batch if c.statement == "np_kin.fk(q)").result.median
    numpy_rate = BATCH / (numpy_batch * 1e-9)
    ours_call = next(c for c in fk if c.result.ours).result.median
    # Pinocchio's FK with the pose copied out: the faster of the two ways measured.
    pin_copies = [c.result for c in fk if "homogeneous" in c.statement and c.result.values]
    pin_copy = min(pin_copies, key=lambda r: r.median) if pin_copies else fk[-1].result
    checks = [
        (
            f"generated C FK + geometric Jacobian under {TARGET_C_FK_JACOBIAN_NS:g} ns per call "
            "in a C loop",
            f"{ns_text(c_fkj)} ns",
            c_fkj < TARGET_C_FK_JACOBIAN_NS,
        ),
        (
            f"batched C entry point ≥ {TARGET_BATCH_C_PER_S / 1e6:g} M configurations/s from "
            "Python",
            f"{batch_c / 1e6:.2f} M/s",
            batch_c >= TARGET_BATCH_C_PER_S,
        ),
        (
            f"NumPy batch FK ≥ {TARGET_BATCH_NUMPY_PER_S / 1e6:g} M configurations/s",
            f"{numpy_rate / 1e6:.2f} M/s",
            numpy_rate >= TARGET_BATCH_NUMPY_PER_S,
        ),
    ]
    if pin_copy.median is not None:
        checks.append(
            (
                "a single FK call from Python no slower than Pinocchio's FK with the pose "
                "copied out",
                f"{ns_text(ours_call)} ns vs {ns_text(pin_copy.median)} ns (fastest Pinocchio "
                "copy-out)",
                ours_call <= pin_copy.median,
            )
        )
    else:
        checks.append(
            (
                "a single FK call from Python no slower than Pinocchio's",
                peers.missing.get("pinocchio", "—"),
                None,
            )
        )
    checks.append(
        (
            f"FK + Jacobian at most {TARGET_OPERATIONS} operations",
            f"{ours_ops['total']}",
            ours_ops["total"] <= TARGET_OPERATIONS,
        )
    )
    checks += peer_targets(c_results, C_LOOP_ROBOTS, C_LOOP_LABELS)
    lines += ["", "### Targets", "", "| target | measured | |", "| --- | ---: | --- |"]
    for text, measured, met in checks:
        verdict = "not measured" if met is None else ("met" if met else "**NOT met**")
        lines.append(f"| {text} | {measured} | {verdict} |")
    lines += [
        "",
        "Every peer's pose (and Jacobian) was checked against symkin's at 20 random joint "
        f"vectors before timing, to {TOLERANCE:g}; the C-loop checksums of symkin's and "
        "both CasADi codes agree. " + " ".join(peers.notes),
    ]
    return "\n".join(lines)


def write_docs(
    table: str,
    path: Path,
    markers: tuple[str, str] = (BEGIN, END),
    heading: str = "Generated-code speed",
) -> None:
    """Put ``table`` between the ``markers`` in ``path`` (appending a section when missing)."""
    begin, end = markers
    block = f"{begin}\n{table}\n{end}"
    text = path.read_text() if path.exists() else "# Benchmarks\n"
    if begin in text and end in text:
        head, rest = text.split(begin, 1)
        _, tail = rest.split(end, 1)
        text = head + block + tail
    else:
        text = text.rstrip("\n") + f"\n\n## {heading}\n\n{block}\n"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)


# --------------------------------------------------------------------------- main


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats (under a minute)")
    parser.add_argument(
        "--rounds", type=int, help="alternated C-loop rounds (default 5; 2 with --quick)"
    )
    parser.add_argument("--docs", type=Path, default=DOCS, help=f"file to update ({DOCS})")
    parser.add_argument("--no-write", action="store_true", help="print only")
    args = parser.parse_args(argv)
    settings = QUICK if args.quick else FULL
    if args.rounds is not None:
        if args.rounds < 1:
            parser.error("--rounds must be at least 1")
        settings = dataclasses.replace(settings, c_rounds=args.rounds)

    load_start = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="symkin-codegen-speed-") as temporary:
        _progress("generating and building the PUMA 560 code ...")
        b = build(Path(temporary))
        rng = np.random.default_rng(560)
        _progress("building the peers and checking them against symkin ...")
        peers = prepare_peers(b, rng)

        _progress("building the C loops (PUMA 560, Panda; three implementations) ...")
        c_results = c_loop(kinematics_loops(Path(temporary), b.cc, b.flags), settings)

        samples = list(rng.uniform(-np.pi, np.pi, (SAMPLES, 6)))
        fk, jacobian, empty = per_call_contenders()
        time_contenders(
            [empty, *fk],
            samples,
            peers,
            settings.py_repeats,
            settings.py_budget_s,
            settings.py_batch_ns,
            "FK per call",
        )
        time_contenders(
            jacobian,
            samples,
            peers,
            settings.py_repeats,
            settings.py_budget_s,
            settings.py_batch_ns,
            "Jacobian per call",
        )
        Q = rng.uniform(-np.pi, np.pi, (BATCH, 6))
        batch = batch_contenders()
        time_contenders(
            batch, [Q], peers, settings.batch_repeats, settings.batch_budget_s, None, "batch FK"
        )
        _progress("counting operations ...")
        ops = operation_counts(b)
        table = render(
            b,
            c_results,
            fk,
            jacobian,
            empty,
            batch,
            ops,
            peers,
            settings,
            args.quick,
            (load_start, os.getloadavg()[0]),
        )
    print(table)
    if not args.no_write:
        write_docs(table, args.docs)
        _progress(f"wrote {args.docs}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
