"""``symkin check EXAMPLE.toml``: a worked example's printed numbers, recomputed.

Exit status 0 when every printed entry is within half a unit of its last digit, 1 when some
are not (each named, with symkin's value and the corrected LaTeX), 2 for a file that cannot
be read (the usual one-line error).
"""

from __future__ import annotations

import argparse

from symkin.cli.report import json_text
from symkin.solve.check import CheckResult, ExampleResult, check_example
from symkin.text import printable


def add_check(commands: argparse._SubParsersAction) -> None:
    """The ``check`` sub-parser."""
    check = commands.add_parser(
        "check",
        help="recompute a worked example's printed numbers and list every mismatch",
        description="Read a worked example (robot, configuration and the printed results: "
        "matrices, angles, table rows; format in docs/worked-examples.md), recompute every "
        "entry and report each one that differs from its printed value by more than half a "
        "unit of the last printed digit, with the corrected LaTeX. Exit status 0: all match; "
        "1: some do not; 2: the file cannot be used.",
    )
    check.add_argument("example", metavar="EXAMPLE.toml", help="the worked example")
    check.add_argument("--json", action="store_true", help="print a JSON object")
    check.set_defaults(run=command_check)


def command_check(args: argparse.Namespace) -> int:
    result = check_example(args.example)
    print(json_text(check_json(result)) if args.json else check_text(result))
    return 0 if result.matches else 1


def _label(result: CheckResult) -> str:
    check = result.check
    at = f" at q = ({', '.join(f'{v:g}' for v in check.q)})" if check.q is not None else ""
    return f"[{check.index}] {printable(check.name)}{at}"


def check_text(outcome: ExampleResult) -> str:
    """One line per check; each mismatching entry with printed value, symkin's value and the
    difference; the corrected LaTeX of a check with mismatches."""
    example = outcome.example
    lines = [f"{printable(str(example.path))}: {printable(example.title) or '(no title)'}"]
    if example.source:
        lines.append(f"source: {printable(example.source)}")
    wrong = 0
    for result in outcome.results:
        count = len(result.entries)
        bad = result.mismatches
        if not bad:
            lines.append(f"  {_label(result)}: {count} entries, all match")
            continue
        wrong += 1
        lines.append(f"  {_label(result)}: {len(bad)} of {count} entries do not match")
        for entry in bad:
            position = (
                f"row {result.check.labels[entry.row - 1]}, column {entry.column}"
                if result.check.labels
                else f"({entry.row}, {entry.column})"
            )
            lines.append(
                f"    {position}: printed {entry.printed.text}, symkin {entry.computed:.6g} "
                f"(differs by {abs(entry.computed - entry.printed.value):.2g}, "
                f"allowed {entry.printed.tolerance:.2g})"
            )
        lines.append("    corrected LaTeX:")
        lines += [f"      {line}" for line in result.latex.splitlines()]
    total = len(outcome.results)
    lines.append(
        f"all {total} checks match" if not wrong else f"{wrong} of {total} checks do not match"
    )
    return "\n".join(lines)


def check_json(outcome: ExampleResult) -> dict:
    """``matches`` and per check its entries (printed text, value, tolerance, symkin's
    value, match) and the corrected LaTeX."""
    return {
        "example": str(outcome.example.path),
        "matches": outcome.matches,
        "checks": [
            {
                "index": r.check.index,
                "name": r.check.name,
                "quantity": r.check.quantity,
                "matches": not r.mismatches,
                "latex": r.latex,
                "entries": [
                    {
                        "row": e.row,
                        "column": e.column,
                        "printed": e.printed.text,
                        "tolerance": e.printed.tolerance,
                        "computed": e.computed,
                        "matches": e.matches,
                    }
                    for e in r.entries
                ],
            }
            for r in outcome.results
        ],
    }
