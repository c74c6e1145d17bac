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
    """One number per sample; a timeout counts as infinitely long, an error not at all."""
    values = []
    for s in samples:
        if s.timeout is not None:
            values.append(math.inf)
        elif s.error is None and (what in ("wall", "cpu", "rss_mb") or "seconds" in s.result):
            values.append(getattr(s, what) if what != "seconds" else s.result["seconds"])
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
    if what == "rss_mb":
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
        return "—" if what == "rss_mb" else f"> {_limit(samples):g} s (timeout)"
    text = _number(value, what)
    if timeouts:
        text += f" ({timeouts} of {len(samples)} timed out)"
    return text


def pair_cell(results: Results, key: tuple) -> str:
    """``wall (CPU)`` of a ``symkin derive`` run."""
    wall = cell(results, key, "wall")
    if not results.samples.get(key) or median_of(results.samples[key], "wall") in (None, math.inf):
        return wall
    return f"{wall} ({cell(results, key, 'cpu')})"


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
        cell(results, k("cold"), "rss_mb"),
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
    return [fit("cold", "cpu"), fit("warm", "cpu"), "", *(fit(kind) for kind in kinds), "", "", ""]


def _table(header: str, rows: list[list[str]]) -> list[str]:
    return [
        f"| {header} | " + " | ".join(COLUMNS) + " |",
        "| --- | " + " | ".join("---:" for _ in COLUMNS) + " |",
        *("| " + " | ".join(row) + " |" for row in rows),
    ]


def targets(results: Results, groups: list[str]) -> list[str]:
    """The issue's targets for ``symkin derive``, judged on median CPU time."""
    lines = []
    for n, limit in ((6, 10.0), (7, 20.0), (12, 120.0)):
        for group in groups:
            samples = results.samples.get((group, n, "cold"), [])
            value = median_of(samples, "cpu")
            if value is None:
                continue
            verdict = "met" if value < limit else "NOT met"
            shown = "timeout" if math.isinf(value) else f"{seconds_text(value)} s CPU"
            lines.append(f"- {n} joints, {group}: cold < {limit:g} s: {shown}, {verdict}")
    warm = [
        (median_of(s, "cpu"), key)
        for key, s in results.samples.items()
        if key[2] == "warm" and median_of(s, "cpu") is not None
    ]
    if warm:
        slowest, key = max(warm, key=lambda item: item[0])
        verdict = "met" if slowest < 1.0 else "NOT met"
        shown = "timeout" if math.isinf(slowest) else f"{seconds_text(slowest)} s CPU"
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

# A ``--verbose`` line giving a phase's elapsed time: "<phase> ... 1.23 s" (any punctuation).
PHASE_LINE = re.compile(
    r"^\W*(?P<name>[A-Za-z].*?)[\s:.,(—-]+(?P<seconds>\d+(?:\.\d+)?)\s*s\)?\s*$"
)


def phases_of(stderr: str) -> dict[str, float]:
    """Elapsed seconds by phase from ``symkin derive --verbose`` (summed over repeats)."""
    phases: dict[str, float] = {}
    for line in stderr.splitlines():
        match = PHASE_LINE.match(line.strip())
        if match:
            name = match["name"].strip()
            phases[name] = phases.get(name, 0.0) + float(match["seconds"])
    return phases


def phase_lines(results: Results, keys: list[tuple]) -> list[str]:
    """The slowest phases of the cold runs (first seed), when ``--verbose`` reports them."""
    lines = []
    for key in keys:
        samples = [s for s in results.samples.get(key, []) if s.error is None and not s.timeout]
        phases = phases_of(samples[0].stderr) if samples else {}
        if phases:
            top = sorted(phases.items(), key=lambda item: -item[1])[:4]
            shown = ", ".join(f"{name} {seconds_text(s)} s" for name, s in top)
            lines.append(f"- {key[0]}, {key[1]}: {shown}")
    return lines


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
        f"{run['minutes']:.0f} min. Sizes {', '.join(map(str, run['sizes']))} joints, "
        f"{run['seeds']} seed{'s' if run['seeds'] > 1 else ''} per size (medians), CPU limit "
        f"{args.timeout:g} s per process. This build's `symkin derive` "
        + ("has `--no-cache`" if "--no-cache" in run["options"] else "has no disk cache")
        + (" and `--verbose`" if "--verbose" in run["options"] else "")
        + ". Generated by `bench/derivation_scaling.py`.",
    ]
    for group in run["groups"]:
        rows = [[str(n), *row_cells(results, group, n)] for n in run["sizes"]]
        rows.append(["growth", *growth_row(results, group, run["sizes"])])
        lines += ["", f"### {GROUP_TITLES[group]}", "", *_table("joints", rows)]
    if run["named"]:
        rows = [[name, *row_cells(results, "named", name)] for name in run["named"]]
        lines += ["", "### Named arms", "", *_table("robot", rows)]
    goals = targets(results, run["groups"])
    if goals:
        lines += ["", "Targets of issue 15 (median CPU time of the whole command):", "", *goals]
    keys = [(g, 6, "cold") for g in run["groups"]] + [("named", n, "cold") for n in run["named"]]
    phases = phase_lines(results, keys)
    if phases:
        lines += ["", "Slowest phases of the cold run (`--verbose`, wall seconds):", "", *phases]
    remarks = notes(results)
    if remarks:
        lines += ["", "Notes:", "", *remarks]
    return "\n".join(lines)
