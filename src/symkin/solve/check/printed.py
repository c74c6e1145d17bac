"""Numbers as a book prints them, and the tolerance they carry: half a unit in the last digit.

``"0.8660"`` has four decimals, so it stands for any value within ``0.00005`` of 0.866;
``"1.2e-3"`` stands for 1.2e-3 +- 0.05e-3.  A TOML number (``0.866``) counts the digits of
its shortest form.  An integer (``0``, ``1``, ``-1``) printed among decimals is exact to the
finest precision of its neighbours (a rotation matrix printing ``0`` and ``0.8660`` means an
exact zero, not ``0 +- 0.5``): :func:`with_neighbours`.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, replace

from symkin.errors import SymkinError

NUMBER = re.compile(r"^\s*([+-]?)(\d*)(?:\.(\d*))?(?:[eE]([+-]?\d+))?\s*$")
# An example whose entries are all integers is compared to this.
INTEGER_TOLERANCE = 5e-5


@dataclass(frozen=True)
class PrintedNumber:
    """A printed value, its text and half a unit of its last digit (``tolerance``);
    ``integer``: printed without decimals."""

    text: str
    value: float
    tolerance: float
    integer: bool
    decimals: int


def printed_number(item: object, where: str) -> PrintedNumber:
    """``item`` (a TOML string or number) as a :class:`PrintedNumber`; ``where`` names it in
    errors."""
    if isinstance(item, bool) or not isinstance(item, int | float | str):
        raise SymkinError(f'{where}: expected a number as printed (e.g. "0.8660"), got {item!r}')
    text = item if isinstance(item, str) else repr(item)
    match = NUMBER.match(text.replace(",", ".", 1) if text.count(",") == 1 else text)
    if not match or not (match.group(2) or match.group(3)):
        raise SymkinError(f"{where}: {text!r} is not a number")
    decimals = len(match.group(3) or "")
    exponent = int(match.group(4) or 0)
    value = float(match.group(0).replace(",", "."))
    if not math.isfinite(value):
        raise SymkinError(f"{where}: {text!r} is not a finite number")
    integer = match.group(3) is None and not match.group(4)
    return PrintedNumber(
        text.strip(), value, 0.5 * 10.0 ** (exponent - decimals), integer, decimals
    )


def with_neighbours(numbers: Sequence[PrintedNumber]) -> list[PrintedNumber]:
    """Integers among decimals take the finest tolerance of the decimals; all integers: exact
    to :data:`INTEGER_TOLERANCE`."""
    decimals = [n.tolerance for n in numbers if not n.integer]
    finest = min(decimals) if decimals else INTEGER_TOLERANCE
    return [replace(n, tolerance=finest) if n.integer else n for n in numbers]


def printed_like(value: float, model: PrintedNumber) -> str:
    """``value`` as ``model`` was printed: as many decimals (or in the same scientific form);
    an integer stays an integer when ``value`` is one within the tolerance, else it gets four
    decimals, so that a wrong ``0`` shows its real value."""
    if model.integer:
        nearest = round(value)
        if abs(value - nearest) <= model.tolerance:
            return str(int(nearest))
        return f"{value:.4f}"
    if "e" in model.text.lower():
        return f"{value:.{model.decimals}e}"
    return f"{value:.{model.decimals}f}"
