"""Progress of long work: named phases and one-line notes, shown by whoever installed a reporter.

The library only marks where its phases begin and end (``with phase("the geometric Jacobian"):``)
and what it wants said (:func:`note`, :func:`detail`); it prints nothing itself.  A front end
(the ``symkin`` command) installs a :class:`Reporter` for the duration of its work with
:func:`reporting`; without one every call here is a no-op, so library users see nothing.

The reporter lives in a context variable, not a module global, so two threads (or a test and
the command it runs) never see each other's reporter.
"""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Protocol

__all__ = ["Reporter", "detail", "note", "phase", "reporting"]


class Reporter(Protocol):
    """What a front end does with the library's phases and messages."""

    def started(self, name: str) -> None:
        """Phase ``name`` began (phases nest: a Jacobian phase runs the kinematics phase)."""

    def finished(self, name: str, seconds: float) -> None:
        """Phase ``name`` ended (normally or by an exception) after ``seconds`` of wall time."""

    def said(self, message: str, verbose: bool) -> None:
        """A message for the user; ``verbose`` ones are shown only on request."""


_REPORTER: ContextVar[Reporter | None] = ContextVar("symkin_reporter", default=None)


@contextmanager
def reporting(reporter: Reporter | None) -> Iterator[None]:
    """Send the phases and messages of the enclosed work to ``reporter`` (None: silence)."""
    token = _REPORTER.set(reporter)
    try:
        yield
    finally:
        _REPORTER.reset(token)


@contextmanager
def phase(name: str) -> Iterator[None]:
    """Mark the enclosed work as phase ``name`` (a noun phrase: "the geometric Jacobian")."""
    reporter = _REPORTER.get()
    if reporter is None:
        yield
        return
    start = time.perf_counter()
    reporter.started(name)
    try:
        yield
    finally:
        reporter.finished(name, time.perf_counter() - start)


def note(message: str) -> None:
    """A line the user should always see (what a long command is doing now)."""
    reporter = _REPORTER.get()
    if reporter is not None:
        reporter.said(message, verbose=False)


def detail(message: str) -> None:
    """A line for ``--verbose`` only (cache hits, why an entry was ignored)."""
    reporter = _REPORTER.get()
    if reporter is not None:
        reporter.said(message, verbose=True)
