"""How the ``symkin`` command shows the library's progress (:mod:`symkin.progress`) on stderr.

* On a terminal (and not ``--json``): one live line per running phase with a spinner and its
  elapsed time (rich), erased when the phase ends, so stdout and the final screen stay clean.
* ``--verbose``: a ``symkin: 12.34 s  the geometric Jacobian`` line per finished phase (nested
  phases indented) and the cache's details; also when stderr is not a terminal.
* Notes (``symkin: deriving puma560 ...``) are always printed, above the live lines.
"""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING, TextIO

from symkin.text import printable

if TYPE_CHECKING:
    from rich.progress import Progress, TaskID


class CommandReporter:
    """A :class:`symkin.progress.Reporter` for one command run."""

    def __init__(self, verbose: bool, live: bool, stream: TextIO | None = None) -> None:
        self.verbose = verbose
        self.live = live
        self.stream = stream or sys.stderr
        self.running: list[TaskID | None] = []
        self.display: Progress | None = None

    def started(self, name: str) -> None:
        if not self.live:
            self.running.append(None)
            return
        if self.display is None:
            # Imported here: rich costs 0.1 s to import, and only a terminal needs it.
            from rich.console import Console
            from rich.progress import Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

            self.display = Progress(
                SpinnerColumn(),
                TextColumn("{task.description}"),
                TimeElapsedColumn(),
                console=Console(file=self.stream, highlight=False),
                transient=True,
                # Never capture the command's own output: stdout must stay pure (JSON, code).
                redirect_stdout=False,
                redirect_stderr=False,
            )
            self.display.start()
        indent = "  " * len(self.running)
        self.running.append(self.display.add_task(f"symkin: {indent}{printable(name)}"))

    def finished(self, name: str, seconds: float) -> None:
        task = self.running.pop() if self.running else None
        if self.display is not None and task is not None:
            self.display.remove_task(task)
        if self.verbose:
            self._line(f"{'  ' * len(self.running)}{seconds:8.2f} s  {name}")
        if self.display is not None and not self.running:
            self.display.stop()
            self.display = None

    def said(self, message: str, verbose: bool) -> None:
        if self.verbose or not verbose:
            self._line(message)

    def close(self) -> None:
        """Stop a live display still running (an interrupt between a phase's start and its
        bookkeeping), so the terminal gets its cursor back whatever happened."""
        if self.display is not None:
            self.display.stop()
            self.display = None
        self.running.clear()

    def _line(self, text: str) -> None:
        line = f"symkin: {printable(text)}"
        if self.display is not None:
            self.display.console.print(line, markup=False, highlight=False, soft_wrap=True)
        else:
            print(line, file=self.stream, flush=True)


def command_reporter(verbose: bool, json_output: bool) -> CommandReporter:
    """The reporter for a command: live lines only on a terminal and never with ``--json``."""
    return CommandReporter(verbose, live=sys.stderr.isatty() and not json_output)
