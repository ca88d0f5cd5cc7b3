"""Print sympy expressions as plain-float Python that uses only the ``math`` module.

Numbers print as ``repr(float)`` (the shortest text that reads back to the
same double), small integer powers of a symbol or number as products (``x*x``
is faster than ``x**2`` in CPython), square roots as ``math.sqrt``. A power of
anything bigger prints as a power, so that its base is evaluated once; the
straight-line builder names such bases first (``Block.finish``), so generated
code unrolls only powers of names. An inverse square root stays ``x**(-0.5)``,
one call of ``pow``: ``1/math.sqrt(x)`` rounds twice and gives another double
for about a quarter of all x (docs/compiler.md). A fractional power of a base that may be
negative prints as ``math.pow``: ``**`` would give a complex number where C's ``leg_pow``
flags, and ``math.pow`` raises there.
"""

from __future__ import annotations

from collections.abc import Mapping
from functools import lru_cache

from sympy import Expr, Float, Integer, Pow, Rational, Symbol
from sympy.printing.precedence import PRECEDENCE
from sympy.printing.pycode import PythonCodePrinter

from legdsl.lower.straightline import is_unrolled_power


class LegPrinter(PythonCodePrinter):
    """The printer for generated legdsl modules.

    ``names`` gives the printed name of a symbol whose own name only orders terms
    (see ``legdsl.lower.straightline.Program``); ``bases`` names the bases of
    powers that are printed as products.
    """

    def __init__(
        self,
        names: Mapping[Symbol, str] | None = None,
        bases: Mapping[Expr, Symbol] | None = None,
    ):
        super().__init__({"fully_qualified_modules": True})
        self._names = names or {}
        self._bases = bases or {}

    def print(self, expr: Expr) -> str:
        """One expression as Python source (fractions as floats: they run as floats anyway)."""
        fractions = {r: Float(r) for r in expr.atoms(Rational) if not r.is_Integer}
        return str(self.doprint(expr.xreplace(fractions) if fractions else expr))

    def _as_ordered_terms(self, expr: Expr, order: str | None = None) -> list[Expr]:
        order = order or self.order
        if order in ("old", "none"):
            return list(super()._as_ordered_terms(expr, order))
        return list(_ordered_terms(expr, order))

    def _print_Symbol(self, expr: Symbol) -> str:
        name = self._names.get(expr)
        return name if name is not None else str(super()._print_Symbol(expr))

    def _print_Float(self, expr: Float) -> str:
        return repr(float(expr))

    def _print_Integer(self, expr: Integer) -> str:
        return repr(float(int(expr)))

    def _print_Rational(self, expr: Rational) -> str:
        return repr(float(expr))

    def _print_Mul(self, expr: Expr) -> str:
        """A product; one unrolled power alone in the denominator is put in parentheses.

        sympy writes a single denominator factor after ``/`` without parentheses, since a
        power binds tighter than a division; but an unrolled power prints as a product,
        and ``a/k*k`` would read back as ``a``: it is written ``a/(k*k)``.
        """
        text = str(super()._print_Mul(expr))
        below = [
            f for f in expr.as_ordered_factors()
            if f.is_Pow and f.exp.is_Rational and f.exp.is_negative
        ]  # fmt: skip
        if len(below) != 1 or below[0].exp == -1:
            return text
        factor = Pow(below[0].base, -below[0].exp, evaluate=False)
        shown = self.parenthesize(factor, PRECEDENCE["Mul"])
        if "*" in shown and not shown.startswith("(") and text.endswith("/" + shown):
            return f"{text[: -len(shown)]}({shown})"
        return text

    def _print_Pow(self, expr: Pow, rational: bool = False) -> str:
        base, exp = expr.as_base_exp()
        if is_unrolled_power(expr):
            named = self._bases.get(expr.base)
            if named is not None:
                factor = self._print(named)
            elif expr.base.is_Atom:
                factor = self.parenthesize(expr.base, PRECEDENCE["Mul"], strict=True)
            else:  # a bare power still evaluates its base once
                factor = ""
            if factor:
                product = "*".join([factor] * abs(int(expr.exp)))
                return product if expr.exp > 0 else f"1/({product})"
        if exp == -1:
            return f"1/{self.parenthesize(base, PRECEDENCE['Mul'], strict=True)}"
        if _is_half(exp):
            return f"math.sqrt({self._print(base)})"
        if not _whole(exp) and not _never_negative(base):
            # Python's ** gives a complex number for a negative base and a fractional power,
            # where C's leg_pow flags: math.pow raises there (ValueError), and is the same pow
            return f"math.pow({self._print(base)}, {self._print(exp)})"
        base_text = self.parenthesize(base, PRECEDENCE["Pow"], strict=True)
        return f"{base_text}**{self.parenthesize(exp, PRECEDENCE['Pow'], strict=True)}"

    def _print_Min(self, expr: Expr) -> str:
        """``minimum``, defined in each control module: min() would keep its first argument
        against a NaN, so a sensor not measured yet vanished or not by sympy's order."""
        return f"minimum({', '.join(self._print(a) for a in expr.args)})"

    def _print_Max(self, expr: Expr) -> str:
        return f"maximum({', '.join(self._print(a) for a in expr.args)})"

    def _print_re(self, expr: Expr) -> str:
        """The real part of a value, which is real (sympy makes ``abs(exp(x))`` ``exp(re(x))``:
        its symbols are not declared real); the C printer does the same."""
        return f"({self._print(expr.args[0])})"

    def _print_im(self, expr: Expr) -> str:
        """The imaginary part of a real value: 0 (``abs(x / exp(1 / (0.25 + y)))`` comes out of
        sympy with ``im(y)``, for the same reason as ``re``); the C printer does the same."""
        return "0.0"

    def _print_sign(self, expr: Expr) -> str:
        """sign(NaN) is NaN, so that the state machine faults on it (``math.copysign`` of a NaN,
        sympy's print, is 1 or -1: a setpoint from a stance time before the first stance ran on
        silently at full deflection); the C printer does the same."""
        x = self._print(expr.args[0])
        return f"(0.0 if ({x}) == 0 else math.copysign(1.0, {x}) if ({x}) == ({x}) else math.nan)"


# Each sum is printed several times (Python, C, the C slices) and sympy orders its terms anew
# each time, a third of all printing: the order depends on the sum alone, so it is kept.
@lru_cache(maxsize=1 << 16)
def _ordered_terms(expr: Expr, order: str | None) -> tuple[Expr, ...]:
    return tuple(expr.as_ordered_terms(order=order))


def _whole(exp: Expr) -> bool:
    """Whether a power is a whole number (a negative base raised to it is real)."""
    return bool(exp.is_Integer or (exp.is_Float and float(exp).is_integer()))


def _never_negative(e: Expr) -> bool:
    """Whether ``e`` is never negative for real values of what it reads: a positive number,
    an even power, and sums and products of them (``x*x + z*z``)."""
    if e.is_Number:
        return bool(e.is_nonnegative)
    if e.is_Add or e.is_Mul:
        return all(_never_negative(a) for a in e.args)
    if e.is_Pow:
        return _whole(e.exp) and int(e.exp) % 2 == 0
    return False


def _is_half(exp: Expr) -> bool:
    """1/2 as sympy writes a square root, or 0.5 once fractions have become floats."""
    return bool(exp == Rational(1, 2) or (exp.is_Float and float(exp) == 0.5))


_PRINTER = LegPrinter()


def print_expr(expr: Expr) -> str:
    """One expression as Python source, its symbols under their own names."""
    return _PRINTER.print(expr)
