"""``symkin check EXAMPLE.toml``: recompute a worked example's printed numbers, entry by entry.

A lecturer types a worked example as a textbook prints it (the robot, the configuration and
the printed results) into a small TOML file (:mod:`~symkin.solve.check.example`, format in
docs/worked-examples.md); :func:`check_example` recomputes every entry with symkin and
reports each mismatch beyond half a unit of the printed last digit
(:mod:`~symkin.solve.check.printed`), with the corrected LaTeX
(:mod:`~symkin.solve.check.compare`).
"""

from symkin.solve.check.compare import CheckResult, EntryResult, ExampleResult, check_example
from symkin.solve.check.example import CHECKS, Check, WorkedExample, read_example
from symkin.solve.check.printed import PrintedNumber, printed_number

__all__ = [
    "CHECKS",
    "Check",
    "CheckResult",
    "EntryResult",
    "ExampleResult",
    "PrintedNumber",
    "WorkedExample",
    "check_example",
    "printed_number",
    "read_example",
]
