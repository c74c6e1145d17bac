"""The Markdown of ``bench/derivation_scaling.py``: samples, medians, ratios, growth, notes."""

from __future__ import annotations

import argparse
import datetime
import math
import os
import platform
import re
import statistics
from dataclasses import dataclass, field

from derivation_time import cpu_model, seconds_text, version
from scaling_children import PEER_KINDS

# What one round measures, in order: (key, column heading).
KINDS = (
    ("cold", "derive cold"),
    ("warm", "derive warm"),
    ("fkj", "FK + J"),
    ("tau", "tau"),
    ("full", "full dynamics"),
    ("sb-tau", "SymPyBotics tau"),
    ("sb-full", "SymPyBotics full set"),
    ("pin", "Pinocchio rnea"),
)


@dataclass
class Sample:
    """One process: wall and CPU seconds, peak RSS, the child's JSON, or why it has none."""

    wall: float | None = None
    cpu: float | None = None
    rss_mb: float | None = None
    result: dict = field(default_factory=dict)
    stderr: str = ""
    timeout: float | None = None  # the limit it reached
    error: str | None = None


@dataclass(frozen=True)
class Arm:
    """A robot to measure: ``group`` is "twists/lengths" for random arms, "named" otherwise."""

    label: str
    group: str
    joints: int
    source: str  # catalogue name or path of a robot file


@dataclass
class Results:
    """Samples by (group, joints or label, kind), and which measurements stopped at a size."""

    samples: dict[tuple[str, object, str], list[Sample]] = field(default_factory=dict)
    stopped: dict[tuple[str, str], int] = field(default_factory=dict)  # -> joints that timed out
    not_run: dict[tuple[str, object, str], str] = field(default_factory=dict)

    def add(self, arm: Arm, kind: str, sample: Sample) -> None:
        self.samples.setdefault(key_of(arm, kind), []).append(sample)
        if sample.timeout is not None and arm.group != "named":
            previous = self.stopped.get((arm.group, kind), arm.joints)
            self.stopped[(arm.group, kind)] = min(previous, arm.joints)


def key_of(arm: Arm, kind: str) -> tuple[str, object, str]:
    return (arm.group, arm.label if arm.group == "named" else arm.joints, kind)


def _values(samples: list[Sample], what: str) -> list[float]:
    """One number per sample (an attribute, or a key of its JSON); a timeout counts as
    infinitely long, an error or a missing figure not at all."""
    values = []
    for s in samples:
        value = getattr(s, what) if what in ("wall", "cpu", "rss_mb") else s.result.get(what)
        if s.timeout is not None:
            values.append(math.inf)
        elif s.error is None and value is not None:
            values.append(value)
    return values


def median_of(samples: list[Sample], what: str) -> float | None:
    values = _values(samples, what)
    return statistics.median(values) if values else None


def _limit(samples: list[Sample]) -> float:
    """The limit the timed-out samples reached."""
    return next(s.timeout for s in samples if s.timeout is not None)


def _number(value: float, what: str) -> str:
    if what == "rnea":
        return f"{value * 1e6:.2f}"
    if what.endswith("rss_mb"):
        return f"{value:.0f}"
    return seconds_text(value)


def cell(results: Results, key: tuple, what: str = "seconds") -> str:
    """Median over the seeds, "> T s (timeout)", the error, or why it was not run."""
    samples = results.samples.get(key, [])
    if not samples:
        return "not run" if key in results.not_run else "—"
    value = median_of(samples, "seconds" if what == "rnea" else what)
    timeouts = sum(s.timeout is not None for s in samples)
    if value is None:
        return samples[-1].error or "—"
    if math.isinf(value):
        return "—" if what.endswith("rss_mb") else f"> {_limit(samples):g} s (timeout)"
    text = _number(value, what)
    if timeouts:
        text += f" ({timeouts} of {len(samples)} timed out)"
    return text


def pair_cell(results: Results, key: tuple) -> str:
    """``wall (CPU)`` of a ``symkin derive`` run: CPU of symkin's own process, without the C
    compiler it runs (that is in the wall time, and in the notes)."""
    wall = cell(results, key, "wall")
    if not results.samples.get(key) or median_of(results.samples[key], "wall") in (None, math.inf):
        return wall
    return f"{wall} ({cell(results, key, 'own_cpu')})"


def ratio(results: Results, peer: tuple, ours: tuple) -> str:
    """Peer median / symkin median (how many times longer the peer takes)."""
    theirs, mine = (median_of(results.samples.get(k, []), "seconds") for k in (peer, ours))
    if theirs is None or mine is None or mine <= 0 or math.isinf(mine):
        return "—"
    if math.isinf(theirs):
        return f"> {_limit(results.samples[peer]) / mine:.1f}×"
    return f"{theirs / mine:.2f}×" if theirs / mine < 10 else f"{theirs / mine:.0f}×"


COLUMNS = (
    "derive cold, wall (CPU) [s]",
    "derive warm, wall (CPU) [s]",
    "peak RSS cold [MB]",
    "FK + J [s]",
    "tau [s]",
    "full dynamics [s]",
    "SymPyBotics tau [s]",
    "SymPyBotics full set [s]",
    "tau: SymPyBotics / symkin",
    "full: SymPyBotics / symkin",
    "Pinocchio rnea [µs/call]",
)


def row_cells(results: Results, group: str, which: object) -> list[str]:
    def k(kind: str) -> tuple:
        return (group, which, kind)

    return [
        pair_cell(results, k("cold")),
        pair_cell(results, k("warm")),
        cell(results, k("cold"), "own_rss_mb"),
        cell(results, k("fkj")),
        cell(results, k("tau")),
        cell(results, k("full")),
        cell(results, k("sb-tau")),
        cell(results, k("sb-full")),
        ratio(results, k("sb-tau"), k("tau")),
        ratio(results, k("sb-full"), k("full")),
        cell(results, k("pin"), "rnea"),
    ]


def growth_exponent(points: list[tuple[int, float]]) -> str:
    """Least-squares slope of log(time) over log(joints): time ~ joints^k."""
    points = [(n, t) for n, t in points if t is not None and 0 < t < math.inf]
    if len(points) < 3:
        return "—"
    xs, ys = [math.log(n) for n, _ in points], [math.log(t) for _, t in points]
    mx, my = statistics.fmean(xs), statistics.fmean(ys)
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys, strict=True))
    slope /= sum((x - mx) ** 2 for x in xs)
    return f"n^{slope:.1f}"


def growth_row(results: Results, group: str, sizes: list[int]) -> list[str]:
    def fit(kind: str, what: str = "seconds") -> str:
        medians = [(n, median_of(results.samples.get((group, n, kind), []), what)) for n in sizes]
        return growth_exponent(medians)

    kinds = ("fkj", "tau", "full", "sb-tau", "sb-full")
    cold, warm = fit("cold", "own_cpu"), fit("warm", "own_cpu")
    return [cold, warm, "", *(fit(kind) for kind in kinds), "", "", ""]


def _table(header: str, rows: list[list[str]]) -> list[str]:
    return [
        f"| {header} | " + " | ".join(COLUMNS) + " |",
        "| --- | " + " | ".join("---:" for _ in COLUMNS) + " |",
        *("| " + " | ".join(row) + " |" for row in rows),
    ]


def targets(results: Results, groups: list[str]) -> list[str]:
    """The issue's targets for ``symkin derive``, judged on the median CPU time of symkin's own
    process (not the C compiler's, not the waiting for the CPU that the wall time includes)."""
    lines = []
    for n, limit in ((6, 10.0), (7, 20.0), (12, 120.0)):
        for group in groups:
            samples = results.samples.get((group, n, "cold"), [])
            value = median_of(samples, "own_cpu")
            if value is None:
                continue
            verdict = "met" if value < limit else "NOT met"
            shown = "timeout" if math.isinf(value) else f"{seconds_text(value)} s"
            lines.append(f"- {n} joints, {group}: cold < {limit:g} s: {shown}, {verdict}")
    warm = [
        (median_of(s, "own_cpu"), key)
        for key, s in results.samples.items()
        if key[2] == "warm" and median_of(s, "own_cpu") is not None
    ]
    if warm:
        slowest, key = max(warm, key=lambda item: item[0])
        verdict = "met" if slowest < 1.0 else "NOT met"
        shown = "timeout" if math.isinf(slowest) else f"{seconds_text(slowest)} s"
        lines.append(
            f"- warm command < 1 s: slowest median {shown} ({key[0]}, {key[1]}), {verdict}"
        )
    return lines


GROUP_TITLES = {
    "right/numeric": "Twists from {0, ±90°}, numeric lengths",
    "right/symbolic": "Twists from {0, ±90°}, symbolic lengths",
    "generic/numeric": "Generic twists, numeric lengths",
    "generic/symbolic": "Generic twists, symbolic lengths",
}

# A ``symkin derive --verbose`` phase line, printed when the phase ends: "symkin:", an indent
# that grows with the nesting, the wall seconds, the phase ("symkin:     2.12 s  the numpy
# files"); a nested phase ends, and is printed, before the phase that contains it.
PHASE_LINE = re.compile(r"^symkin:(?P<indent> +)(?P<seconds>\d+(?:\.\d+)?) s +(?P<name>\S.*)$")
CACHE_HIT = "cache: derive of"  # the --verbose line of a run that read the cache


def phases_of(stderr: str) -> tuple[dict[str, float], dict[str, float]]:
    """``(outermost, nested)`` phases of a ``--verbose`` run: wall seconds by phase name,
    summed over repeats (the same phase runs again for each backend's kernels)."""
    found = [(len(m["indent"]), m["name"], float(m["seconds"])) for m in
             (PHASE_LINE.match(line.rstrip()) for line in stderr.splitlines()) if m]  # fmt: skip
    outer = min((indent for indent, _, _ in found), default=0)
    phases: tuple[dict[str, float], dict[str, float]] = ({}, {})
    for indent, name, seconds in found:
        table = phases[0] if indent == outer else phases[1]
        table[name] = table.get(name, 0.0) + seconds
    return phases


def _slowest(phases: dict[str, float], count: int) -> str:
    top = sorted(phases.items(), key=lambda item: -item[1])[:count]
    return ", ".join(f"{name} {seconds_text(s)} s" for name, s in top)


def phase_lines(results: Results, keys: list[tuple]) -> list[str]:
    """The phases of the first cold run of each key, when ``--verbose`` reports them."""
    lines = []
    for key in keys:
        samples = [s for s in results.samples.get(key, []) if s.error is None and not s.timeout]
        outer, nested = phases_of(samples[0].stderr) if samples else ({}, {})
        if outer:
            inside = f"; slowest inside: {_slowest(nested, 3)}" if nested else ""
            lines.append(f"- {key[0]}, {key[1]}: {_slowest(outer, 4)}{inside}")
    return lines


def compiler_line(results: Results) -> list[str]:
    """The C compiler's share of the ``symkin derive`` runs (left out of their CPU column)."""
    runs = [s for key, ss in results.samples.items() if key[2] in ("cold", "warm") for s in ss]
    cpu, rss = _values(runs, "compiler_cpu"), _values(runs, "compiler_rss_mb")
    cpu, rss = [v for v in cpu if v < math.inf], [v for v in rss if v < math.inf]
    if not cpu:
        return []
    return [
        f"- The C compiler that `symkin derive` runs to build the Python extension took "
        f"{seconds_text(statistics.median(cpu))} s CPU per run (median; {seconds_text(min(cpu))} "
        f"to {seconds_text(max(cpu))} s), peak RSS at most {max(rss):.0f} MB (an upper bound: "
        "its `ru_maxrss` includes symkin's own peak, which Linux carries through the fork and "
        "`exec`); it is in the wall times, not in the CPU times or the RSS column."
    ]


def cache_line(results: Results) -> list[str]:
    """How many warm runs said (``--verbose``) that they read the cold run's cache entry."""
    warm = [s for key, ss in results.samples.items() if key[2] == "warm" for s in ss]
    finished = [s for s in warm if s.error is None and s.timeout is None]
    if not finished:
        return []
    hits = sum(CACHE_HIT in s.stderr for s in finished)
    return [f"- Warm runs that read the cache (their `--verbose` says so): {hits} of {len(warm)}."]


# The same-arm checks the children make before (Pinocchio) or after (SymPyBotics) timing.
CHECKS = (
    (
        ("pin",),
        "- Pinocchio's torques matched the inverse dynamics of symkin's generated NumPy module "
        "on 10 random states in each of {count} runs: largest difference {worst:.0e} of the "
        "largest torque.",
    ),
    (
        PEER_KINDS,
        "- SymPyBotics' last-link pose matched the numeric product of the DH table "
        "(`tests/numeric_dh.py`) at 3 random configurations in each of {count} runs: largest "
        "difference {worst:.0e}.",
    ),
)


def notes(results: Results) -> list[str]:
    """Why cells say "not run", and the same-arm checks of the peers."""
    names = dict(KINDS)
    reasons: dict[tuple[str, str], dict[str, list[str]]] = {}
    for (group, which, kind), reason in results.not_run.items():
        reasons.setdefault((kind, reason), {}).setdefault(group, []).append(str(which))
    lines = [
        f"- {names[kind]}: not run ({reason}): "
        + "; ".join(f"{group} {', '.join(which)}" for group, which in groups.items())
        for (kind, reason), groups in reasons.items()
    ]
    for kinds, text in CHECKS:
        checks = [
            s.result["checked"]
            for key, samples in results.samples.items()
            if key[2] in kinds
            for s in samples
            if s.result.get("checked") is not None
        ]
        if checks:
            lines.append(text.format(count=len(checks), worst=max(checks)))
    return lines


def render(results: Results, args: argparse.Namespace, run: dict) -> str:
    today = datetime.datetime.now(datetime.UTC).date().isoformat()
    sb = run["sympybotics"]
    lines = [
        f"Measured on {today}: {cpu_model()}, {os.cpu_count()} cores; Python "
        f"{platform.python_version()}, symkin {version('symkin')}, SymPy {version('sympy')}, "
        f"SymEngine {version('symengine')}, Pinocchio (`pin`) {version('pin')}, SymPyBotics {sb}. "
        f"Load average (1 min) at the start and end: {run['load'][0]:.1f} and "
        f"{run['load'][1]:.1f} (2 cores shared with other work); the run took "
        f"{run['minutes']:.1f} min. Sizes {', '.join(map(str, run['sizes']))} joints, "
        f"{run['seeds']} seed{'s' if run['seeds'] > 1 else ''} per size (medians), CPU limit "
        f"{args.timeout:g} s per process. This build's `symkin derive` "
        + ("has `--no-cache`" if "--no-cache" in run["options"] else "has no disk cache")
        + (" and `--verbose`" if "--verbose" in run["options"] else "")
        + ". Generated by `bench/derivation_scaling.py`.",
    ]
    for group in run["groups"]:
        rows = [[str(n), *row_cells(results, group, n)] for n in run["sizes"]]
        if len(run["sizes"]) >= 3:  # a slope needs three sizes
            rows.append(["growth", *growth_row(results, group, run["sizes"])])
        lines += ["", f"### {GROUP_TITLES[group]}", "", *_table("joints", rows)]
    if run["named"]:
        rows = [[name, *row_cells(results, "named", name)] for name in run["named"]]
        lines += ["", "### Named arms", "", *_table("robot", rows)]
    goals = targets(results, run["groups"])
    if goals:
        lines += [
            "",
            "Targets of issue 15 (median CPU seconds of symkin's own process, the whole command):",
            "",
            *goals,
        ]
    keys = [(g, 6, "cold") for g in run["groups"]] + [("named", n, "cold") for n in run["named"]]
    phases = phase_lines(results, keys)
    if phases:
        lines += [
            "",
            "Phases of the cold run (`--verbose`, wall seconds; outermost phases, then the "
            "slowest phases nested in them):",
            "",
            *phases,
        ]
    remarks = notes(results) + cache_line(results) + compiler_line(results)
    if remarks:
        lines += ["", "Notes:", "", *remarks]
    return "\n".join(lines)
