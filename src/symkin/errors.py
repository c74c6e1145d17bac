"""The one exception type for user mistakes (bad files, bad arguments).

The command line prints its message and exits with status 2; it never shows a traceback for
a :class:`SymkinError`.  Anything else escaping is a bug in symkin.
"""


class SymkinError(Exception):
    """A user mistake with a message that says what was expected."""


class RobotError(SymkinError):
    """An invalid robot description (file, joint, key and what was expected)."""
