"""An input or parameter declared as a plain number, used where a quantity is needed:
``param stroke = 3`` (3 cm meant), then ``leg_spring.rest = stroke``.

The unit left out is the declaration's mistake, so it is told there, with the caret under
the number and the unit to write; each use that needs the same unit tells the same words
at the same place, which are shown once (``Diagnostics.raise_if_any``). Uses wanting
another unit each tell their own.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from legdsl.check.control_words import describe_type
from legdsl.ir import controller as ir
from legdsl.ir.controller import BOOL, ONE
from legdsl.lang import ast
from legdsl.lang.errors import Span
from legdsl.lang.units import KINDS, describe

# input or parameter -> its kind and the value it is declared with, for those declared as a
# plain number (no unit written)
Unitless = Mapping[str, tuple[str, ast.Expr]]


def plain_declared(
    unitless: Unitless, values: Sequence[ir.Expr], needed: ir.Type = None
) -> tuple[Span, str] | None:
    """The error at the declaration of the one input or parameter among ``values`` declared
    as a plain number, where the others (and what is ``needed`` of them all) have one
    dimension that is not a plain number; None if there is no such one."""
    plain = [
        v
        for v in values
        if isinstance(v, ir.Named) and v.kind in ("input", "param") and v.name in unitless
    ]
    others = {t for t in [needed, *(v.type for v in values if v not in plain)] if t is not None}
    if len(plain) != 1 or len(others) != 1 or others & {ONE, BOOL}:
        return None
    (want,) = others
    assert isinstance(want, tuple) and isinstance(plain[0], ir.Named)
    name = plain[0].name
    kind, value = unitless[name]
    unit = next((u for d, u in KINDS.values() if d == want), None)
    text = number_text(value)
    advice = (
        f"as in '{kind} {name} = {text} {unit}'"
        if unit is not None and text is not None
        else f"with a unit of {describe(want)}"
    )
    word = "parameter" if kind == "param" else kind
    return (
        value.span,
        f"{word} '{name}' is declared as a plain number (no unit), but it is used as "
        f"{describe_type(want)}; declare it with its unit, {advice}",
    )


def number_text(value: ast.Expr) -> str | None:
    """A declaration's value as written, its sign too ('-3', '200 N*m'); None if it is no
    number."""
    if isinstance(value, ast.EUnary) and value.op == "-":
        inner = number_text(value.operand)
        return None if inner is None else f"-{inner}"
    return value.text if isinstance(value, ast.EQuantity) else None
