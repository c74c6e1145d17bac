"""The one exception type for user mistakes (bad files, bad arguments).

The command line prints its message and exits with status 2; it never shows a traceback for
a :class:`SymkinError`.  Anything else escaping is a bug in symkin.
"""

import string
from collections.abc import Mapping


class SymkinError(Exception):
    """A user mistake with a message that says what was expected."""


class RobotError(SymkinError):
    """An invalid robot description (file, joint, key and what was expected)."""


class RobotWarning(UserWarning):
    """A robot description that loads but looks suspicious (e.g. inertia data that no rigid
    body can have but that published models use, such as lumped link inertias)."""


class _Templated:
    """A message whose parameter names are ``str.format`` fields, spelled by the front end."""

    def __init__(self, template: str) -> None:
        self.template = template
        self.parameters = tuple(
            name for _, name, _, _ in string.Formatter().parse(template) if name
        )
        super().__init__(self.message_for({}))

    def message_for(self, spellings: Mapping[str, str]) -> str:
        """The message with each parameter spelled as ``spellings`` says (else its name)."""
        return self.template.format(**{name: spellings.get(name, name) for name in self.parameters})


class ParameterError(_Templated, SymkinError):
    """A bad argument of a library function, named as the function names it.

    ``template`` marks each argument name as a ``str.format`` field; build the rest with an
    f-string and doubled braces: ``ParameterError(f"{{q}} needs {n} values")``.  The library's
    message names the Python parameter (``q needs 6 values``); a front end spells it its own
    way through :meth:`message_for` (the CLI: ``--q needs 6 values``), so the library never
    speaks of flags.
    """


class BudgetWarning(_Templated, UserWarning):
    """An optional closed form (factored determinant, singular set, adjugate inverse, symbolic
    manipulability) not found within its time budget; the message names the parameter that
    changes the budget as a template field, like :class:`ParameterError`."""


def literal(value: object) -> str:
    """``str(value)`` for a :class:`ParameterError` template: braces doubled, so a value a user
    typed (``'{x}'``) prints as given instead of being read as a parameter name."""
    return str(value).replace("{", "{{").replace("}", "}}")
