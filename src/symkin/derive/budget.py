"""Time budgets for the optional closed forms, so that no derivation hangs.

The factored determinant, the singular configurations, the adjugate inverse and the symbolic
manipulability are extras: the generated code can compute the determinant and the
manipulability numerically from the Jacobian.  The readable (angle-sum contracted) forward
kinematics and Jacobian of a long chain are extras too (:mod:`symkin.derive.readable`): their
product form has the same values.  Each is computed under a budget of wall-clock seconds
(:data:`DEFAULT_BUDGET_SECONDS`); past it the result is a :class:`ClosedForm` whose
status says so, and one :class:`BudgetWarning` line tells the user which result, which robot,
the budget and how to change it.

How the deadline is enforced: the step runs in a forked child process that sends its result
back through a private pipe (pickled SymPy objects: the bytes come from our own child, never
from a file); the parent waits at most the budget and then kills the child.  A process, not a
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

# Seconds per optional closed form.  Every catalogue robot needs under 0.3 s (UR5 det 0.1 s),
# a generic 6R arm's determinant about 6 s (2 shared cores); 20 s bounds what a user waits.
DEFAULT_BUDGET_SECONDS = 20.0

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
    """The step did not finish within its budget (internal; callers get a ClosedForm)."""


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
    except OverBudgetError:
        warning = BudgetWarning(
            f"{robot}: the {quantity} was not found within the budget of {budget:g} s; "
            f"{fallback} (a larger {{budget}} allows more time)"
        )
        warnings.warn(warning, stacklevel=4)
        return ClosedForm(quantity, OVER_BUDGET, None, warning.message_for({}))
    return ClosedForm(quantity, FOUND, value)


def not_attempted(quantity: str, robot: str) -> ClosedForm:
    """The result when closed forms are switched off."""
    note = f"{robot}: the {quantity} closed form was not attempted (switched off)"
    return ClosedForm(quantity, NOT_ATTEMPTED, None, note)


def run_within(seconds: float | None, compute: Callable[[], Any]) -> Any:
    """``compute()`` in a forked child, or :class:`OverBudgetError` after ``seconds``."""
    if seconds is None or not hasattr(os, "fork"):
        return compute()
    reader, writer = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: compute, send, leave without running the parent's exit hooks
        os.close(reader)
        _send(writer, compute)
    os.close(writer)
    try:
        data = _receive(reader, time.monotonic() + seconds)
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


def _receive(reader: int, deadline: float) -> bytes:
    chunks = []
    while True:
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            raise OverBudgetError
        ready, _, _ = select.select([reader], [], [], remaining)
        if ready:
            chunk = os.read(reader, 1 << 20)
            if not chunk:
                break
            chunks.append(chunk)
    if not chunks:
        raise ArithmeticError("the closed-form step stopped without a result")
    return b"".join(chunks)


def _stop(pid: int) -> None:
    """Kill the child if it still runs, and reap it."""
    with contextlib.suppress(ProcessLookupError):
        os.kill(pid, signal.SIGKILL)
    os.waitpid(pid, 0)
