"""Generated modules imported from the runtime layer's private directory (no ``exec``)."""

from __future__ import annotations

import atexit
import os
import tempfile
import threading

import pytest

from symkin.errors import SymkinError
from symkin.runtime import modules
from symkin.runtime.modules import module_from_source


def test_the_same_code_is_one_file_and_other_code_another():
    first = module_from_source("def f(x):\n    return 2 * x\n", "double")
    again = module_from_source("def f(x):\n    return 2 * x\n", "double")
    other = module_from_source("def f(x):\n    return 3 * x\n", "double")
    assert first.__file__ == again.__file__ != other.__file__
    assert (first.f(4), other.f(4)) == (8, 12)
    assert not [p for p in os.listdir(os.path.dirname(first.__file__)) if p.endswith(".tmp")]


@pytest.mark.slow
def test_threads_loading_the_same_code_never_see_a_half_written_file():
    # A long source makes a torn write likely if writers shared a staging file.
    source = "".join(f"c{i} = {i}\n" for i in range(20000)) + "total = c19999\n"
    errors: list[BaseException] = []
    results: list[int] = []

    def load() -> None:
        try:
            for _ in range(5):
                results.append(module_from_source(source, "threads").total)
        except BaseException as error:  # every failure is the finding
            errors.append(error)

    threads = [threading.Thread(target=load) for _ in range(8)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert not errors
    assert results == [19999] * 40


def test_no_writable_temporary_directory_is_one_clear_error(monkeypatch):
    monkeypatch.setattr(modules, "_DIRECTORIES", {})
    monkeypatch.setattr(tempfile, "tempdir", "/nonexistent/symkin-test")
    with pytest.raises(SymkinError, match="TMPDIR"):
        module_from_source("x = 1\n", "nowhere")


def test_a_forked_child_does_not_remove_its_parents_directory():
    parent_module = module_from_source("x = 1\n", "parent")
    directory = os.path.dirname(parent_module.__file__)
    pid = os.fork()
    if pid == 0:  # the child: load code, then run the exit handlers as a normal exit would
        module_from_source("y = 2\n", "child")
        atexit._run_exitfuncs()
        os._exit(0)
    _, status = os.waitpid(pid, 0)
    assert os.waitstatus_to_exitcode(status) == 0
    assert os.path.isdir(directory)
    assert module_from_source("z = 3\n", "parent").z == 3
