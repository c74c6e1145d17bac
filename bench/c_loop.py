"""The C-loop tables of ``codegen_speed.py`` and ``dynamics_speed.py``: one robot's kernel, in
three implementations, timed by the same C harness, alternated round by round.

The three implementations (``IMPLEMENTATIONS``):

* ``symkin``: symkin's generated C (``c/<robot>.c``);
* ``graph``: the C that ``casadi.CodeGenerator`` writes for symkin's generated CasADi module,
  that is CasADi printing symkin's own expression graph;
* ``peer``: the C that ``casadi.CodeGenerator`` writes for the independent CasADi model of
  ``bench/casadi_peer.py`` (FK as a product of DH transforms, the Jacobian from the joint axes,
  Newton–Euler, forward dynamics by ``casadi.solve``), written from the DH table alone.

Each harness run is its own process: it prints the nanoseconds per call of every timed repeat
(``CLOCK_THREAD_CPUTIME_ID``), a checksum of the outputs and its peak resident set
(``VmHWM`` of ``/proc/self/status``).  Rounds alternate every row, kernel and implementation,
so load that comes and goes falls on all alike.  The checksums of the three implementations of
a kernel must agree (same inputs), else the script stops.
"""

from __future__ import annotations

import statistics
import subprocess
import sys
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path

IMPLEMENTATIONS = {
    "symkin": "**symkin C**",
    "graph": "CasADi C of symkin's graph",
    "peer": "CasADi C, independent model from the DH table",
}
CHECKSUM_TOLERANCE = 1e-9  # relative, between implementations of one kernel


class ChecksumError(RuntimeError):
    """Two implementations of a kernel summed to different checksums: they disagree."""


def casadi_c(functions: Iterable, directory: Path, basename: str) -> Path:
    """``directory/<basename>.c`` (and ``.h``) from ``casadi.CodeGenerator`` for ``functions``."""
    import casadi

    directory.mkdir(parents=True, exist_ok=True)
    generator = casadi.CodeGenerator(f"{basename}.c", {"with_header": True})
    for function in functions:
        generator.add(function)
    generator.generate(f"{directory}/")
    return directory / f"{basename}.c"


def compile_harness(
    cc: str, flags: tuple[str, ...], harness: Path, source: Path, output: Path, *defines: str
) -> Path:
    """``harness`` linked with the kernel ``source`` (its own translation unit), the header
    named like the source; ``-DBENCH_CASADI`` for a CasADi source (not in a folder ``c``)."""
    casadi = source.parent.name != "c"  # symkin writes its C into c/, the benches CasADi's not
    command = [
        cc, *flags, f"-I{source.parent}", f'-DHEADER="{source.stem}.h"',
        *(["-DBENCH_CASADI"] if casadi else []), *defines,
        str(harness), str(source), "-o", str(output), "-lm",
    ]  # fmt: skip
    done = subprocess.run(command, capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise SystemExit(f"compiling {output.name} failed:\n{done.stderr}")
    return output


@dataclass
class Run:
    """One (row, kernel, implementation): ns per call of every repeat, checksum, peak RSS."""

    values: list[float] = field(default_factory=list)
    checksum: float | None = None
    max_rss_kib: list[int] = field(default_factory=list)

    @property
    def median(self) -> float | None:
        return statistics.median(self.values) if self.values else None


@dataclass(frozen=True)
class Job:
    """A harness command: ``row`` (a robot or build), ``kernel``, ``impl``."""

    row: str
    kernel: str
    impl: str
    command: tuple[str, ...]


def run_rounds(jobs: list[Job], rounds: int) -> dict[tuple[str, str, str], Run]:
    """Every job once per round, in order, ``rounds`` times; then the checksums compared."""
    runs = {(j.row, j.kernel, j.impl): Run() for j in jobs}
    for round_ in range(rounds):
        for job in jobs:
            done = subprocess.run(job.command, capture_output=True, text=True, check=True)
            run = runs[job.row, job.kernel, job.impl]
            for line in done.stdout.splitlines():
                key, value = line.split()
                if key == "ns_per_call":
                    run.values.append(float(value))
                elif key == "checksum":
                    run.checksum = float(value)
                elif key == "max_rss_kib":
                    run.max_rss_kib.append(int(value))
        print(
            f"C loop round {round_ + 1}/{rounds}: "
            + ", ".join(f"{'/'.join(k)} {r.values[-1]:.0f}" for k, r in runs.items()),
            file=sys.stderr,
            flush=True,
        )
    check_checksums(runs)
    return runs


def check_checksums(runs: dict[tuple[str, str, str], Run]) -> None:
    for (row, kernel, impl), run in runs.items():
        ours = runs[row, kernel, "symkin"].checksum
        theirs = run.checksum
        if ours is None or theirs is None:
            raise ChecksumError(f"C loop {row} {kernel} {impl}: no checksum")
        if not abs(ours - theirs) <= CHECKSUM_TOLERANCE * max(1.0, abs(ours)):
            raise ChecksumError(
                f"C loop {row} {kernel}: checksums differ, symkin {ours!r}, {impl} {theirs!r}"
            )


def _ns(value: float | None) -> str:
    if value is None:
        return "—"
    return f"{value:.1f}" if value < 100 else f"{value:,.0f}"


def table(
    runs: dict[tuple[str, str, str], Run],
    rows: dict[str, str],
    kernels: dict[str, str],
) -> list[str]:
    """Markdown rows: one per (row, kernel), ns per call and ratio to symkin of every
    implementation, and the peak RSS of the three harness processes."""
    header = "| code | kernel | " + " | ".join(
        f"{label} [ns/call] | ratio" if impl != "symkin" else f"{label} [ns/call]"
        for impl, label in IMPLEMENTATIONS.items()
    )
    lines = [
        header + " | peak RSS symkin / graph / independent [MiB] |",
        "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    for row, row_label in rows.items():
        for kernel, kernel_label in kernels.items():
            if (row, kernel, "symkin") not in runs:
                continue
            ours = runs[row, kernel, "symkin"].median
            cells = [_ns(ours)]
            rss = []
            for impl in IMPLEMENTATIONS:
                run = runs[row, kernel, impl]
                rss.append(f"{max(run.max_rss_kib) / 1024:.1f}" if run.max_rss_kib else "—")
                if impl == "symkin":
                    continue
                ratio = run.median / ours if run.median and ours else None
                cells += [_ns(run.median), "—" if ratio is None else f"{ratio:.2f}×"]
            cells.append(" / ".join(rss))
            lines.append(f"| {row_label} | {kernel_label} | {' | '.join(cells)} |")
    return lines


def peer_targets(
    runs: dict[tuple[str, str, str], Run], rows: dict[str, str], kernels: dict[str, str]
) -> list[tuple[str, str, bool | None]]:
    """The issue's target for every (row, kernel): symkin's C at or below the independent
    CasADi model's C in the same C loop; ``(target, measured, met)``."""
    checks: list[tuple[str, str, bool | None]] = []
    for row, row_label in rows.items():
        for kernel, kernel_label in kernels.items():
            if (row, kernel, "symkin") not in runs:
                continue
            ours, peer = runs[row, kernel, "symkin"].median, runs[row, kernel, "peer"].median
            met = None if ours is None or peer is None else ours <= peer
            checks.append(
                (
                    f"{row_label}: C {kernel_label} at or below the independent CasADi C "
                    "in the same C loop",
                    f"{_ns(ours)} ns vs {_ns(peer)} ns",
                    met,
                )
            )
    return checks


METHOD = (
    "Each figure is the median over all rounds of the per-repeat CPU time per call "
    "(`CLOCK_THREAD_CPUTIME_ID`, the loop and a checksum of the outputs included), every "
    "harness run its own process; the rounds alternate every code, kernel and implementation "
    "(symkin C, then CasADi C of symkin's graph, then the independent CasADi model), and all "
    "three are compiled with the same flags against the same harness and inputs, the kernel in "
    "its own translation unit. *CasADi C of symkin's graph* is `casadi.CodeGenerator` on "
    "symkin's generated CasADi module (symkin's expressions, CasADi's printer). *CasADi C, "
    "independent model from the DH table* is `casadi.CodeGenerator` on `bench/casadi_peer.py`: "
    "FK as the product of the DH transforms (standard or modified), the Jacobian columns "
    "`[z × (p − o); z]` from those products, Newton–Euler in link frames, and forward "
    "dynamics as a CasADi user writes it (M by n unit-acceleration Newton–Euler passes, the "
    "bias by one pass at ddq = 0, then `casadi.solve(M, tau − bias)`, which on `SX` unrolls "
    "a QR factorisation), with every parameter a number. symkin's forward dynamics factorises "
    "M by Cholesky. Before timing, the peer's outputs were checked against symkin's at random "
    "inputs, and the three implementations' checksums agree to 1e-9 relative. *Peak RSS* is "
    "the harness process's own high-water mark (`VmHWM` in `/proc/self/status`, largest over "
    "the rounds; `ru_maxrss` would carry the Python parent's peak across `exec`): "
    "mostly the harness's table of inputs (3 MiB of joint vectors, 9 MiB of states for six "
    "joints) and the C runtime, the same for all three, so it shows only what the kernel's code "
    "and work arrays add."
)
