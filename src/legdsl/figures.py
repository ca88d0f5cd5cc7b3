"""Numbers as a person reads them in legdsl's tables and summaries.

Three decimals suit a creature of about a metre. A creature scaled by Table 1 to a few
millimetres has strides of 0.0008 m and energies of 1e-10 J, which three decimals print as
0.000; a giant's energies run to two hundred digits. So a figure keeps three decimals and
at least two significant digits (a creature of ordinary size reads as before), and a spread
(a standard deviation) is printed to its value's decimals, as a measurement and its
uncertainty are.
"""

from __future__ import annotations

import math

MOST_DECIMALS = 6  # past this, powers of ten read better than a row of zeros
GIANT = 1e9  # from here, powers of ten: 1.007e+10 J, not 10070000000.000 J


def _decimals(x: float) -> int:
    """How many decimals show ``x`` to two significant digits (three at the least)."""
    if x == 0 or not math.isfinite(x):
        return 3
    return max(3, 1 - math.floor(math.log10(abs(x))))


def figure(x: float, like: float | None = None) -> str:
    """``x`` with three decimals, or as many as two significant digits of ``like`` (``x``
    itself when not given) need; "n/a" when not finite."""
    if not math.isfinite(x):
        return "n/a"
    scale = abs(x) if like is None or not math.isfinite(like) else abs(like)
    if max(abs(x), scale) >= GIANT:
        return f"{x:.4g}"
    places = _decimals(scale)
    if places > MOST_DECIMALS:  # three significant digits; a spread to its value's last one
        return f"{x if like is None else round(x, places + 1):.3g}"
    return f"{x:.{places}f}"


def figures(values: tuple[float, ...] | list[float]) -> str:
    """A vector's components to the decimals of its largest one: "(0.120, 0.000, 0.845)"."""
    largest = max((abs(v) for v in values if math.isfinite(v)), default=0.0)
    return "(" + ", ".join(figure(v, largest) for v in values) + ")"
