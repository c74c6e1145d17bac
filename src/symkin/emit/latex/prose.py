"""The words of the LaTeX derivation, one TOML file per language.

``templates/latex/prose/<lang>.toml`` (package data of ``symkin.templates``) holds the
headings, introductions and the text between displays as LaTeX; the file's header says which
values are ``str.format`` templates.
"""

from __future__ import annotations

import tomllib
from collections.abc import Mapping
from functools import cache
from importlib import resources
from types import MappingProxyType

from symkin.errors import ParameterError, literal

LANGUAGES = ("en", "de")


def check_language(lang: str) -> str:
    """``lang`` if it is one of :data:`LANGUAGES`."""
    if lang not in LANGUAGES:
        raise ParameterError(
            f"{{lang}} must be one of {', '.join(LANGUAGES)}, got {literal(repr(lang))}"
        )
    return lang


@cache
def prose(lang: str) -> Mapping[str, str]:
    """The prose in language ``lang`` (see :data:`LANGUAGES`), read once."""
    path = resources.files("symkin.templates") / "latex" / "prose" / f"{check_language(lang)}.toml"
    return MappingProxyType(tomllib.loads(path.read_text(encoding="utf-8")))
