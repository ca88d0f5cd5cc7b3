"""Print sympy expressions as plain-float Python that uses only the ``math`` module.

Numbers print as ``repr(float)`` (the shortest text that reads back to the
same double), small integer powers as products (``x*x`` is faster than
``x**2`` in CPython), square roots as ``math.sqrt``.
"""

from __future__ import annotations

from typing import Any

from sympy import Expr, Float, Integer, Pow, Rational
from sympy.printing.precedence import PRECEDENCE
from sympy.printing.pycode import PythonCodePrinter

# Powers up to this exponent are printed as repeated multiplication.
MAX_UNROLLED_POWER = 4


class LegPrinter(PythonCodePrinter):
    """The printer for generated legdsl modules."""

    def __init__(self, settings: dict[str, Any] | None = None):
        super().__init__({"fully_qualified_modules": True, **(settings or {})})

    def _print_Float(self, expr: Float) -> str:
        return repr(float(expr))

    def _print_Integer(self, expr: Integer) -> str:
        return repr(float(int(expr)))

    def _print_Rational(self, expr: Rational) -> str:
        return repr(float(expr))

    def _print_Pow(self, expr: Pow, rational: bool = False) -> str:
        base, exp = expr.as_base_exp()
        if exp.is_Integer and 1 < abs(int(exp)) <= MAX_UNROLLED_POWER:
            factor = self.parenthesize(base, PRECEDENCE["Mul"], strict=True)
            product = "*".join([factor] * abs(int(exp)))
            return product if exp > 0 else f"1/({product})"
        if exp == -1:
            return f"1/{self.parenthesize(base, PRECEDENCE['Mul'], strict=True)}"
        if exp == Rational(1, 2):
            return f"math.sqrt({self._print(base)})"
        if exp == Rational(-1, 2):
            return f"1/math.sqrt({self._print(base)})"
        return f"{self.parenthesize(base, PRECEDENCE['Pow'], strict=True)}**{self.parenthesize(exp, PRECEDENCE['Pow'], strict=True)}"


_PRINTER = LegPrinter()


def print_expr(expr: Expr) -> str:
    """One expression as Python source (fractions as floats: they run as floats anyway)."""
    fractions = {r: Float(r) for r in expr.atoms(Rational) if not r.is_Integer}
    return str(_PRINTER.doprint(expr.xreplace(fractions) if fractions else expr))
