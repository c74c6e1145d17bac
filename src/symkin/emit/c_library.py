"""The symkin C library: the fixed C algorithms as real sources in ``templates/c/lib``.

Each source compiles on its own (``real_t`` is ``double``, or ``float`` with ``SYMKIN_FLOAT``);
a generated file pastes the ones it needs into itself (``templates/c/library.j2``), so that a
generated folder needs nothing else to build.
"""

from __future__ import annotations

# Parts of the library, each a header and a source, in an order where every part comes after
# the parts it calls.
PARTS = ("xorshift", "pose_error", "cholesky", "cholesky_columns", "dls")


def library_files(precision: str, *parts: str) -> list[str]:
    """File names (in ``templates/c/lib``) to paste for ``parts`` in ``precision``: the real
    type first, then each part's header and source, in dependency order."""
    files = [f"symkin_real_{precision}.h"]
    for part in sorted(parts, key=PARTS.index):
        files += [f"symkin_{part}.h", f"symkin_{part}.c"]
    return files
