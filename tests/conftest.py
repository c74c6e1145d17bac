"""Shared fixtures.

Deriving a robot is the costly part of most tests, so one model per robot is derived once per
session: the ``model`` fixture is :func:`numeric_dh.model` (cached), which covers the built-in
robots and the two hand-written test robots.  Module-level helpers that need a model outside a
test function import ``numeric_dh.model`` directly; it is the same cache.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator

import pytest

from numeric_dh import model as cached_model
from symkin.derive import Model


@pytest.fixture(scope="session", autouse=True)
def no_user_cache(tmp_path_factory: pytest.TempPathFactory) -> Iterator[None]:
    """Never read or fill the user's derivation cache, nor carry results between tests: the
    cache is off (``SYMKIN_NO_CACHE``, inherited by subprocesses too) and points at a private
    folder; tests of the cache turn it on with their own folder (tests/test_cache.py)."""
    saved = {name: os.environ.get(name) for name in ("SYMKIN_NO_CACHE", "XDG_CACHE_HOME")}
    os.environ["SYMKIN_NO_CACHE"] = "1"
    os.environ["XDG_CACHE_HOME"] = str(tmp_path_factory.mktemp("xdg-cache"))
    yield
    for name, value in saved.items():
        if value is None:
            os.environ.pop(name, None)
        else:
            os.environ[name] = value


@pytest.fixture(scope="session")
def model_of() -> Callable[[str], Model]:
    """``model_of("puma560")``: the session's derived model of a built-in or test robot."""
    return cached_model


#: Six- and seven-joint robots: deriving their dynamics takes seconds each, so a test
#: parametrized with one of them is ``slow`` (``make test-fast`` leaves it to ``make test``).
HEAVY_ROBOTS = frozenset({"panda", "ur5", "puma560", "stanford", "cylindrical_rtt_wrist"})


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    for item in items:
        callspec = getattr(item, "callspec", None)
        if callspec is not None and any(
            isinstance(value, str) and value in HEAVY_ROBOTS for value in callspec.params.values()
        ):
            item.add_marker(pytest.mark.slow)
