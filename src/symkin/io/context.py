"""Where we are in a robot file, for error messages, and the small readers every table uses.

A :class:`Context` carries the file name, the joint (1-based) and the dotted key prefix, so that
every :class:`~symkin.errors.RobotError` reads like::

    robots/arm.toml: joint 2: 'type' must be "revolute" or "prismatic", got "rotary"

It also carries what value conversion needs: the file's angle unit and the declared parameters
(their symbols and default values).
"""

from __future__ import annotations

import difflib
import json
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, replace
from typing import Any

import sympy as sp

from symkin.errors import RobotError


@dataclass(frozen=True)
class Context:
    """Location for error messages plus what value conversion needs (units, parameters)."""

    file: str
    angles: str = "deg"
    symbols: Mapping[str, sp.Symbol] | None = None
    values: Mapping[str, float | None] | None = None
    joint: int | None = None
    prefix: str = ""

    def at_joint(self, index: int) -> Context:
        return replace(self, joint=index, prefix="")

    def within(self, key: str) -> Context:
        return replace(self, prefix=self.key(key) + ".")

    def key(self, key: str) -> str:
        """The dotted key as shown to the user, e.g. ``link.inertia.ixx``."""
        return f"{self.prefix}{key}"

    @property
    def where(self) -> str:
        """The file and joint, ``robots/arm.toml: joint 2``, that start a message."""
        return self.file if self.joint is None else f"{self.file}: joint {self.joint}"

    def error(self, message: str) -> RobotError:
        return RobotError(f"{self.where}: {message}")


def did_you_mean(word: str, choices: Iterable[str]) -> str:
    """`` (did you mean 'x'?)`` for the closest of ``choices``, or an empty string."""
    close = difflib.get_close_matches(word, list(choices), n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


def show(value: Any, depth: int = 0) -> str:
    """A user's value as they wrote it in TOML (shortened), for 'got ...' in messages."""
    if isinstance(value, bool):
        text = "true" if value else "false"
    elif isinstance(value, str):
        text = json.dumps(value, ensure_ascii=False)
    elif isinstance(value, dict):
        return "a table"
    elif isinstance(value, int) and abs(value) > 10**30:
        return "a very large integer"
    elif isinstance(value, int | float):
        text = repr(value)
    elif isinstance(value, list) and depth >= 3:  # TOML arrays may nest arbitrarily deep
        return "[...]"
    elif isinstance(value, list):
        items = ", ".join(show(v, depth + 1) for v in value[:4])
        text = "[" + items + (", ...]" if len(value) > 4 else "]")
    else:
        text = f"{value} (a {type(value).__name__})"  # TOML dates and times
    return text if len(text) <= 60 else text[:57] + "..."


def check_keys(table: Mapping[str, Any], allowed: Iterable[str], ctx: Context) -> None:
    """Raise for the first key of ``table`` not in ``allowed``, with a hint and the list."""
    allowed = tuple(allowed)
    for key in table:
        if key not in allowed:
            raise ctx.error(
                f"unknown key {ctx.key(key)!r}{did_you_mean(key, allowed)}; "
                f"allowed here: {', '.join(allowed)}"
            )


def as_table(value: Any, key: str, ctx: Context) -> dict[str, Any]:
    """``value`` if it is a TOML table, else a located error naming ``key``."""
    if not isinstance(value, dict):
        raise ctx.error(f"{ctx.key(key)!r} must be a table, got {show(value)}")
    return value


def read_choice(table: Mapping[str, Any], key: str, choices: tuple[str, ...], ctx: Context) -> str:
    """``table[key]``, one of ``choices``; a missing key means ``choices[0]``."""
    value = table.get(key, choices[0])
    if value not in choices:
        options = " or ".join(f'"{c}"' for c in choices)
        raise ctx.error(f"{ctx.key(key)!r} must be {options}, got {show(value)}")
    return value


def read_text(table: Mapping[str, Any], key: str, ctx: Context) -> str:
    """``table[key]`` as a string; a missing key means ``""``."""
    value = table.get(key, "")
    if not isinstance(value, str):
        raise ctx.error(f"{ctx.key(key)!r} must be a string, got {show(value)}")
    return value
