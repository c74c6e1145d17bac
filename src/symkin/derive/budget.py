"""Time budgets for the optional closed forms, so that no derivation hangs.

The factored determinant, the singular configurations, the adjugate inverse and the symbolic
manipulability are extras: the generated code can compute the determinant and the
manipulability numerically from the Jacobian.  The readable (angle-sum contracted) forward
kinematics and Jacobian of a long chain are extras too (:mod:`symkin.derive.readable`): their
product form has the same values.  Each is computed under a budget of CPU seconds
(:data:`DEFAULT_BUDGET_SECONDS`); past it the result is a :class:`ClosedForm` whose
status says so, and one :class:`BudgetWarning` line tells the user which result, which robot,
the budget and how to change it.

How the deadline is enforced: the step runs in a forked child process that sends its result
back through a private pipe (pickled SymPy objects: the bytes come from our own child, never
from a file); the parent polls the child's CPU time (user + system, from
``/proc/<pid>/stat``) and kills it once that exceeds the budget.  CPU time, not wall-clock
time, so that the same robot gets the same closed forms on an idle machine and on a loaded
one (two cores shared by a dozen processes gave a 20 s wall-clock budget less than 4 s of
computing).  A wall-clock backstop of :data:`WALL_FACTOR` times the budget still stops a child
that waits instead of computing, or one starved by load.  Where ``/proc`` does not exist
(macOS), the budget is wall-clock time.  A process, not a
signal, because the library may run outside the main thread (a GUI, a web worker), where
``SIGALRM`` cannot be used, and because a process is stopped for sure, whatever the algebra
does.  The heavy prerequisites (kinematics, the Jacobian) are computed in the parent first, so
the child only does the optional step.  Where ``fork`` does not exist (Windows), the step runs
in process without a deadline; the size guards of :mod:`symkin.derive.determinant` still apply.
"""

from __future__ import annotations

import contextlib
import os
import pickle
import select
import signal
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from symkin.errors import BudgetWarning
from symkin.progress import reporting

# CPU seconds per optional closed form.  Every catalogue robot needs under 0.3 s (UR5 det
# 0.1 s); 20 s bounds what a user waits.
DEFAULT_BUDGET_SECONDS = 20.0
# The wall-clock backstop, in budgets: a child sleeping, blocked, or given under a third of a
# core is stopped there.
WALL_FACTOR = 3.0

FOUND = "found"
NOT_SQUARE = "not square"
OVER_BUDGET = "over budget"
NOT_ATTEMPTED = "not attempted"

NUMERIC_FALLBACK = "the generated code computes it numerically from the Jacobian"


@dataclass(frozen=True)
class ClosedForm:
    """An optional closed form: its ``value`` when ``status`` is ``"found"``, else ``None``.

    ``status``: ``"found"``, ``"not square"`` (no determinant, no inverse), ``"over budget"``
    (not found within the budget) or ``"not attempted"`` (closed forms switched off).
    ``note`` is one line for people, empty when found.
    """

    quantity: str
    status: str
    value: Any = None
    note: str = ""

    @property
    def found(self) -> bool:
        return self.status == FOUND


class OverBudgetError(Exception):
    """The step did not finish within its budget (internal; callers get a ClosedForm).

    ``clock`` says which limit stopped it: ``"cpu"`` (the budget) or ``"wall"`` (the
    backstop)."""

    def __init__(self, clock: str) -> None:
        super().__init__(f"stopped by the {clock} limit")
        self.clock = clock


def closed_form_within(
    quantity: str,
    robot: str,
    budget: float | None,
    compute: Callable[[], Any],
    fallback: str = NUMERIC_FALLBACK,
) -> ClosedForm:
    """``compute()`` as a :class:`ClosedForm`, or the over-budget one (with a warning).

    ``budget`` is in seconds; ``None`` means no limit.  ``fallback`` says, in the warning,
    what symkin uses instead.
    """
    try:
        value = run_within(budget, compute)
    except OverBudgetError as stop:
        wall = stop.clock == "wall"
        backstop = f" (wall-clock backstop {WALL_FACTOR * budget:g} s)" if wall else ""
        warning = BudgetWarning(
            f"{robot}: the {quantity} was not found within the budget of {budget:g} s of CPU "
            f"time{backstop}; {fallback} (a larger {{budget}} allows more time)"
        )
        warnings.warn(warning, stacklevel=4)
        return ClosedForm(quantity, OVER_BUDGET, None, warning.message_for({}))
    return ClosedForm(quantity, FOUND, value)


def not_attempted(quantity: str, robot: str) -> ClosedForm:
    """The result when closed forms are switched off."""
    note = f"{robot}: the {quantity} closed form was not attempted (switched off)"
    return ClosedForm(quantity, NOT_ATTEMPTED, None, note)


def run_within(
    seconds: float | None, compute: Callable[[], Any], wall_factor: float = WALL_FACTOR
) -> Any:
    """``compute()`` in a forked child, or :class:`OverBudgetError` once the child has used
    ``seconds`` of CPU time or ``wall_factor * seconds`` of wall-clock time."""
    if seconds is None or not hasattr(os, "fork"):
        return compute()
    reader, writer = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: compute, send, leave without running the parent's exit hooks
        os.close(reader)
        _send(writer, compute)
    os.close(writer)
    try:
        data = _receive(reader, pid, seconds, time.monotonic() + wall_factor * seconds)
    finally:
        os.close(reader)
        _stop(pid)
    kind, payload = pickle.loads(data)
    if kind == "error":
        raise payload
    return payload


def _send(writer: int, compute: Callable[[], Any]) -> None:
    try:
        try:
            data = pickle.dumps(("value", _quietly(compute)))
        except Exception as error:  # the parent re-raises it (or a stand-in that pickles)
            try:
                data = pickle.dumps(("error", error))
            except Exception:
                data = pickle.dumps(("error", ArithmeticError(f"{type(error).__name__}: {error}")))
        with os.fdopen(writer, "wb") as pipe:
            pipe.write(data)
    finally:
        os._exit(0)


def _quietly(compute: Callable[[], Any]) -> Any:
    """``compute()`` with no progress display and no warnings: the forked child must not
    print through the parent's display, whose refresh thread (and its lock) did not survive
    the fork (a lock held at that moment would deadlock the child until its budget ends)."""
    with reporting(None), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return compute()


def child_cpu_seconds(pid: int) -> float | None:
    """User + system CPU seconds of a running child, from ``/proc/<pid>/stat`` (fields 14
    and 15, in clock ticks; proc(5)), or None where there is no ``/proc``."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as file:
            fields = file.read().rsplit(b")", 1)[1].split()
    except OSError:
        return None
    # After the ")" closing the command name, field 3 (state) is the first.
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def _receive(reader: int, pid: int, seconds: float, wall_deadline: float) -> bytes:
    """The child's bytes; :class:`OverBudgetError` past ``seconds`` of its CPU time (polled
    every few hundredths of the budget) or past ``wall_deadline``."""
    chunks = []
    started = time.monotonic()
    poll = min(0.1, max(0.005, seconds / 50))
    while True:
        ready, _, _ = select.select([reader], [], [], poll)
        if ready:
            chunk = os.read(reader, 1 << 20)
            if not chunk:
                break
            chunks.append(chunk)
            continue
        now = time.monotonic()
        if now >= wall_deadline:
            raise OverBudgetError("wall")
        used = child_cpu_seconds(pid)
        if (now - started if used is None else used) > seconds:
            raise OverBudgetError("cpu")
    if not chunks:
        raise ArithmeticError("the closed-form step stopped without a result")
    return b"".join(chunks)


def _stop(pid: int) -> None:
    """Kill the child if it still runs, and reap it."""
    with contextlib.suppress(ProcessLookupError):
        os.kill(pid, signal.SIGKILL)
    os.waitpid(pid, 0)
