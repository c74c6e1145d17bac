"""The whole command users run, ``symkin derive puma560 --out DIR``, against whole peer processes
doing their natural equivalent; part of ``bench/derivation_time.py``.

Every run is a fresh process, measured from the outside (``os.wait4`` through
``derivation_scaling.run_process``): CPU seconds of the process and of every process it waited
for (the C compiler), wall seconds and peak RSS, imports included.  The contenders alternate
round by round (symkin, its two variants, Robotics Toolbox, SymPyBotics; again), each
symkin run with an empty derivation cache (``XDG_CACHE_HOME``), so that load drifting during
the run falls on all of them alike.

* **symkin**: ``symkin derive puma560 --out DIR`` as its console script runs it (NumPy, C,
  CasADi, the CPython extension compiled), the same with ``--no-build``, and with
  ``--regressor`` (the identification kernels too, as SymPyBotics' full set has a regressor).
* **Robotics Toolbox** (``python bench/derivation_whole.py rtb DIR``): what one writes with its
  symbolic mode for the same arm: ``DH.Puma560(symbolic=True)``, ``fkine`` and ``jacob0``,
  ``rne_python`` with symbols for tau, the gravity torque (zero velocity and acceleration) and
  the mass matrix (n unit-acceleration passes without gravity), one ``sympy.cse`` over all of
  them and C code from ``sympy.ccode`` written to ``DIR/rtb_puma560.c``.  RTB's ``inertia`` and
  ``gravload`` refuse symbols, hence the ``rne_python`` passes.
* **SymPyBotics** (only with ``--sympybotics DIR``, a checkout; it is not on PyPI):
  ``RobotDynCode`` (tau, g, c, C, M and the regressor, with its incremental CSE) and C code for
  each, as ``bench/scaling_children.py sb-full`` runs it.  Without a checkout: "not run".
"""

from __future__ import annotations

import json
import statistics
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
ROBOT = "puma560"
CONTENDERS = (
    ("symkin", "`symkin derive puma560 --out DIR`: NumPy, C, CasADi, extension compiled"),
    ("symkin-no-build", "`symkin derive puma560 --out DIR --no-build`: the same, not compiled"),
    (
        "symkin-regressor",
        "`symkin derive puma560 --out DIR --regressor`: the default and the "
        "regressor kernels (SymPyBotics' set includes a regressor)",
    ),
    (
        "rtb",
        "RTB `DH.Puma560(symbolic=True)`: FK, J, tau, G, M by `rne_python`, `sympy.cse`, "
        "C by `sympy.ccode`",
    ),
    ("sympybotics", "SymPyBotics `RobotDynCode`: tau, g, c, C, M, regressor, C code"),
)


# --------------------------------------------------------------------------- the RTB process


def rtb_process(out: str) -> None:
    """The Robotics Toolbox contender: everything, imports included, in this process."""
    import numpy as np
    import roboticstoolbox as rtb
    import spatialmath.base.symbolic as sym
    import sympy

    from derivation_time import peak_rss_mb

    robot = rtb.models.DH.Puma560(symbolic=True)
    n = robot.n
    q, dq, ddq = (sym.symbol(f"{name}1:{n + 1}") for name in ("q", "qd", "qdd"))
    zeros = np.zeros(n)
    outputs = {
        "T": list(robot.fkine(q).A.flat),
        "J": list(robot.jacob0(q).flat),
        "tau": list(robot.rne_python(q, dq, ddq)),
        "G": list(robot.rne_python(q, zeros, zeros)),
    }
    mass = [robot.rne_python(q, zeros, np.eye(n)[j], gravity=[0, 0, 0]) for j in range(n)]
    outputs["M"] = [mass[j][i] for i in range(n) for j in range(n)]
    names = [(key, i) for key, values in outputs.items() for i in range(len(values))]
    entries = [sympy.sympify(v) for values in outputs.values() for v in values]
    replacements, reduced = sympy.cse(entries)
    lines = [
        "#include <math.h>",
        "void rtb_puma560(const double *q, const double *qd, "
        "const double *qdd, double *T, double *J, double *tau, double *G, double *M) {",
    ]
    inputs = {
        s: sympy.Symbol(f"{s.name[:-1].replace('1', '')}[{int(s.name[-1]) - 1}]")
        for s in (*q, *dq, *ddq)
    }
    for symbol, value in replacements:
        lines.append(f"  const double {symbol} = {sympy.ccode(value.xreplace(inputs))};")
    for (key, i), value in zip(names, reduced, strict=True):
        lines.append(f"  {key}[{i}] = {sympy.ccode(value.xreplace(inputs))};")
    lines.append("}")
    Path(out).mkdir(parents=True, exist_ok=True)
    (Path(out) / "rtb_puma560.c").write_text("\n".join(lines) + "\n")
    operations = int(sympy.count_ops([v for _, v in replacements]) + sympy.count_ops(reduced))
    print(json.dumps({"operations": operations, "rss_mb": peak_rss_mb()}))


# --------------------------------------------------------------------------- measuring


def _command(kind: str, out: Path, sympybotics: Path | None) -> list[str]:
    from derivation_scaling import symkin_command

    bench = ROOT / "bench"
    if kind.startswith("symkin"):
        extra = {"symkin-no-build": ["--no-build"], "symkin-regressor": ["--regressor"]}
        return [*symkin_command(), "derive", ROBOT, "--out", str(out), *extra.get(kind, [])]
    if kind == "rtb":
        return [sys.executable, str(bench / "derivation_whole.py"), "rtb", str(out)]
    return [sys.executable, str(bench / "scaling_children.py"), "sb-full", ROBOT, str(sympybotics)]


def measure_whole(repeat: int, timeout: float, sympybotics: Path | None, progress) -> dict:
    """``{kind: [Sample, ...]}``, alternated round by round; SymPyBotics only with a checkout."""
    from derivation_scaling import _env, run_process
    from scaling_children import RUSAGE_TAG

    kinds = [k for k, _ in CONTENDERS if k != "sympybotics" or sympybotics is not None]
    samples: dict[str, list] = {kind: [] for kind in kinds}
    with tempfile.TemporaryDirectory(prefix="symkin-bench-") as folder:
        for round_ in range(repeat):
            for kind in kinds:
                work = Path(tempfile.mkdtemp(dir=folder))
                sample = run_process(
                    _command(kind, work / "out", sympybotics), timeout, _env(work / "cache")
                )
                for line in reversed(sample.stderr.splitlines()):  # symkin's own figures
                    if line.startswith(RUSAGE_TAG):
                        sample.result = json.loads(line.removeprefix(RUSAGE_TAG))
                        break
                samples[kind].append(sample)
                how = sample.error or ("timeout" if sample.timeout else "")
                progress(
                    f"whole {kind:16} round {round_ + 1}/{repeat}: {sample.cpu:.2f} s CPU, "
                    f"{sample.wall:.2f} s wall, {_value(sample, 'rss') or 0:.0f} MB {how}"
                )
    return samples


def _value(sample, key: str) -> float | None:
    """``cpu`` or ``wall`` of a finished run, or ``rss``: the process's own peak (``VmHWM``,
    which it reports itself; ``os.wait4``'s ``ru_maxrss`` would include this parent's)."""
    if sample.error or sample.timeout:
        return None
    if key == "rss":
        return sample.result.get("own_rss_mb", sample.result.get("rss_mb"))
    return getattr(sample, key)


def _values(samples: list, key: str) -> list[float]:
    return [v for v in (_value(s, key) for s in samples) if v is not None]


def _median(samples: list, key: str) -> float | None:
    values = _values(samples, key)
    return statistics.median(values) if values else None


def _range(samples: list, key: str) -> str:
    values = _values(samples, key)
    if not values:
        failed = samples[-1]
        if failed.timeout:
            return f"did not finish in {failed.timeout:g} s"
        return failed.error or "—"
    digits = 0 if key == "rss" else 2
    text = f"{statistics.median(values):.{digits}f}"
    if len(values) == 1:
        return text
    return f"{text} ({min(values):.{digits}f}–{max(values):.{digits}f})"


def render_whole(samples: dict, sympybotics: Path | None) -> list[str]:
    """The Markdown lines of the whole-command table."""
    reference = _median(samples.get("symkin", []), "cpu")
    lines = [
        "### The whole command against whole peer processes (PUMA 560, same run)",
        "",
        "Each row is a fresh process measured from outside (`os.wait4`): CPU seconds of the "
        "process and of the processes it waited for (the C compiler), wall seconds, imports "
        "included; peak RSS is the process's own (`VmHWM`, reported by it at exit; the "
        "compiler's separate process is not added). Median (min–max) of alternated rounds. "
        "The ratio is the median CPU time of `symkin derive` over the contender's (below 1: "
        "symkin takes less). The rows do not make the same files: the first column says "
        "what each makes.",
        "",
        "| contender | CPU [s] | wall [s] | peak RSS [MB] | symkin / contender (CPU) |",
        "| --- | ---: | ---: | ---: | ---: |",
    ]
    for kind, label in CONTENDERS:
        runs = samples.get(kind)
        if runs is None:
            no_checkout = kind == "sympybotics" and sympybotics is None
            why = "not run (no `--sympybotics DIR`)" if no_checkout else "not run"
            lines.append(f"| {label} | {why} | — | — | — |")
            continue
        cpu = _median(runs, "cpu")
        ratio = f"{reference / cpu:.2f}" if cpu and reference else "—"
        lines.append(
            f"| {label} | {_range(runs, 'cpu')} | {_range(runs, 'wall')} "
            f"| {_range(runs, 'rss')} | {ratio} |"
        )
    compiler = [
        s.result["compiler_cpu"]
        for s in samples.get("symkin", [])
        if s.result.get("compiler_cpu") is not None
    ]
    if compiler:
        lines += [
            "",
            f"Of `symkin derive`'s CPU time, the C compiler took {statistics.median(compiler):.2f}"
            " s (median).",
        ]
    return lines


if __name__ == "__main__":
    if sys.argv[1:2] != ["rtb"] or len(sys.argv) != 3:
        raise SystemExit("usage: derivation_whole.py rtb OUT")
    rtb_process(sys.argv[2])
