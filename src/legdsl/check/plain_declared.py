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
from legdsl.lang.units import KINDS, Dim, describe

# input or parameter -> its kind and the value it is declared with, for those declared as a
# plain number (no unit written)
Unitless = Mapping[str, tuple[str, ast.Expr]]


def plain_declared(
    unitless: Unitless, values: Sequence[ir.Expr], needed: ir.Type = None
) -> tuple[Span, str] | None:
    """The error at the declaration of the one input or parameter among ``values`` declared
    as a plain number, where the others (and what is ``needed`` of them all) have one
    dimension that is not a plain number; None if there is no such one."""
    found = lone_declared(unitless, values, needed)
    if found is None:
        return None
    named, want = found
    kind, value = unitless[named.name]
    word = "parameter" if kind == "param" else kind
    return (
        value.span,
        f"{word} '{named.name}' is declared as a plain number (no unit), but it is used as "
        f"{describe_type(want)}; declare it with its unit, "
        f"{advice(kind, named.name, number_text(value), want, 'with')}",
    )


def lone_declared(
    declared: Mapping[str, object], values: Sequence[ir.Expr], needed: ir.Type
) -> tuple[ir.Named, Dim] | None:
    """The one input or parameter among ``values`` named in ``declared``, and the dimension
    the others (and ``needed``) all have, where that is one dimension and not a plain number
    or a truth value; None otherwise (two such names are not blamed on one declaration)."""
    named = [
        v
        for v in values
        if isinstance(v, ir.Named) and v.kind in ("input", "param") and v.name in declared
    ]
    others = {t for t in [needed, *(v.type for v in values if v not in named)] if t is not None}
    if len(named) != 1 or len(others) != 1 or others & {ONE, BOOL}:
        return None
    (want,) = others
    assert isinstance(want, tuple) and isinstance(named[0], ir.Named)
    return named[0], want


def advice(kind: str, name: str, number: str | None, want: Dim, word: str) -> str:
    """How to declare ``name`` in a unit of ``want``: the declaration written out where
    ``number`` and a unit of that kind are known, else the dimension."""
    unit = next((u for d, u in KINDS.values() if d == want), None)
    if unit is not None and number is not None:
        return f"as in '{kind} {name} = {number} {unit}'"
    return f"{word} a unit of {describe(want)}"


def number_text(value: ast.Expr) -> str | None:
    """A declaration's value as written, its sign too ('-3', '200 N*m'); None if it is no
    number."""
    if isinstance(value, ast.EUnary) and value.op == "-":
        inner = number_text(value.operand)
        return None if inner is None else f"-{inner}"
    return value.text if isinstance(value, ast.EQuantity) else None
