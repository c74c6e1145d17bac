"""The ``symkin`` command: a thin layer over the public API.

User mistakes (bad files, bad values) print one ``symkin: error: ...`` line and exit with
status 2; they never show a traceback.  Ctrl-C exits with 130, a bug in symkin with 3.
"""

from __future__ import annotations

import errno
import os
import signal
import sys
import threading
import warnings
from collections.abc import Sequence
from contextlib import closing

from symkin.cli.parser import build_parser
from symkin.cli.report import error_text, show_warning
from symkin.cli.reporter import command_reporter
from symkin.cli.values import join_negative_values
from symkin.errors import SymkinError
from symkin.progress import reporting
from symkin.text import printable


def _is_output_failure(error: Exception) -> bool:
    """A write to standard output that the system refused (a full disk, a quota, an I/O
    error): files symkin writes name themselves in a SymkinError instead."""
    return isinstance(error, OSError) and error.filename is None and error.errno in (
        errno.ENOSPC, errno.EDQUOT, errno.EIO,
    )  # fmt: skip


class TimeLimitReached(BaseException):
    """Raised by the alarm; a BaseException, so SymPy's ``except Exception`` cannot swallow it."""


def _stop_at_time_limit(seconds: float) -> None:
    def expire(*_: object) -> None:
        raise TimeLimitReached

    # Signals reach only the main thread (main() may be called from another, e.g. a GUI).
    if seconds > 0 and threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGALRM, expire)
        signal.setitimer(signal.ITIMER_REAL, seconds)


def _tolerant_output() -> None:
    """A title in a script the terminal's encoding lacks (``PYTHONIOENCODING=ascii``) is
    printed as ``\\u`` escapes rather than failing the command after its work is done."""
    for stream in (sys.stdout, sys.stderr):
        if hasattr(stream, "reconfigure"):
            stream.reconfigure(errors="backslashreplace")


def main(argv: Sequence[str] | None = None) -> int:
    """Run one command (``argv`` defaults to ``sys.argv[1:]``); the exit status."""
    if argv is None:  # the command line's own streams (a caller's are left as they are)
        _tolerant_output()
    parser = build_parser()
    args = parser.parse_args(join_negative_values(sys.argv[1:] if argv is None else argv))
    status = 0
    subject = f"{args.command} {printable(getattr(args, 'robot', '') or '')}".rstrip()
    try:
        _stop_at_time_limit(args.time_limit)
        reporter = command_reporter(getattr(args, "verbose", False), getattr(args, "json", False))
        with warnings.catch_warnings(), reporting(reporter), closing(reporter):
            warnings.showwarning = show_warning
            status = args.run(args) or 0  # ik: 1 when the target is not reached
            sys.stdout.flush()  # a full disk is said here, not at the interpreter's exit
    except SymkinError as error:
        print(error_text(error, args.command), file=sys.stderr)
        return 2
    except TimeLimitReached:
        print(
            f"symkin: error: {subject}: stopped at the time limit of {args.time_limit:g} s "
            "(--time-limit SECONDS, 0 for none); the derivation or the task is too large for it",
            file=sys.stderr,
        )
        return 2
    except KeyboardInterrupt:
        print(f"symkin: {subject}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # Output piped into `head` and closed early: not an error of ours.
        sys.stderr.close()
    except Exception as error:
        if os.environ.get("SYMKIN_TRACEBACK"):
            raise
        if _is_output_failure(error):
            print(f"symkin: error: {subject}: cannot write the output: {error.strerror}",
                  file=sys.stderr)  # fmt: skip
            return 2
        print(
            f"symkin: internal error: {subject}: {type(error).__name__}: "
            f"{printable(str(error))[:300]} (a bug in symkin: please report it with the robot "
            "file; SYMKIN_TRACEBACK=1 shows the traceback)",
            file=sys.stderr,
        )
        return 3
    finally:
        if threading.current_thread() is threading.main_thread():
            signal.setitimer(signal.ITIMER_REAL, 0)
    return status
