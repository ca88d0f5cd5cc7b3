"""Numbers as messages say them: two told apart, one past a double, a percentage written
as a plain number (``legdsl.lang.units`` gives them to the rest of the package)."""

from __future__ import annotations

import math
import re
from decimal import Decimal

_MANTISSA = re.compile(r"\s*[-+]?(\d*\.?\d*)")


def out_of_range(written: str, value: float) -> str | None:
    """Why a number, as written, has no double to hold it: too large (it would be infinite),
    or too small (not zero, yet it would read as 0); None for a number that reads."""
    if not math.isfinite(value):
        return f"'{written}' is too large a number"
    mantissa = _MANTISSA.match(written)
    if value == 0 and mantissa is not None and re.search("[1-9]", mantissa.group(1)):
        return (
            f"'{written}' is too small a number: nearer 0 than a double holds (5e-324), it "
            "would read as 0; write 0 if you mean zero"
        )
    return None


def apart(a: float, b: float, digits: int = 3) -> tuple[str, str]:
    """``a`` and ``b`` to ``digits`` significant digits, or to as many more as tell them apart
    ('fell to 0.2099 m (the limit is 0.21 m)', not 'fell to 0.21 m (the limit is 0.21 m)')."""
    for n in range(digits, 18):
        shown = f"{a:.{n}g}", f"{b:.{n}g}"
        if shown[0] != shown[1] or a == b:
            break
    return shown


def percentage(number: str | None) -> str:
    """The message for a number written as a percentage: the plain number to write instead,
    the user's own (``number``, the digits before '%') where it reads as one."""
    try:
        plain = format(Decimal(number or "").scaleb(-2).normalize(), "f")
    except ArithmeticError:
        return "a percentage is written as a plain number: '0.5', not '50%'"
    return f"a percentage is written as a plain number: '{plain}', not '{number}%'"
