"""The one exception type for user mistakes (bad files, bad arguments).

The command line prints its message and exits with status 2; it never shows a traceback for
a :class:`SymkinError`.  Anything else escaping is a bug in symkin.
"""


class SymkinError(Exception):
    """A user mistake with a message that says what was expected."""


class RobotError(SymkinError):
    """An invalid robot description (file, joint, key and what was expected)."""


class RobotWarning(UserWarning):
    """A robot description that loads but looks suspicious (e.g. inertia data that no rigid
    body can have but that published models use, such as lumped link inertias)."""
