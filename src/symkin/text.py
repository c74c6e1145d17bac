"""Text from users (titles, sources, paths) made safe to show.

A robot file is data from anyone: its text must never act as terminal escape sequences,
reorder a line (bidirectional controls) or end a comment in a generated file.  The loader
rejects such characters in titles and sources (:func:`unprintable_characters`); everything
shown or written still passes through :func:`printable`, for robots built in Python and for
file paths.
"""

from __future__ import annotations

# Line breaks a caller may keep (messages of several lines); everything else unprintable
# (C0/C1 controls, DEL, format characters such as U+202E, separators, surrogates) is escaped.
KEPT = frozenset("\n")


def _escape(character: str) -> str:
    return character.encode("unicode_escape").decode("ascii")


def printable(text: str, keep: frozenset[str] = frozenset()) -> str:
    """``text`` with every character that is not printable written as its escape
    (``\\x1b``, ``\\u202e``, ``\\x00``); characters in ``keep`` stay as they are."""
    return "".join(c if c.isprintable() or c in keep else _escape(c) for c in text)


def unprintable_characters(text: str) -> list[str]:
    """The escapes of the characters that :func:`printable` would escape, in order, unique."""
    return list(dict.fromkeys(_escape(c) for c in text if not c.isprintable()))
