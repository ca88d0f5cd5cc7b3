"""How to fix a value of the wrong unit in a controller's expression: the sentence after
the mistake. ``clamp(ramp, -1, 1 rad)`` told the dimensions apart and stopped there; each
mistake of units now ends saying what to write (``control_exprs`` uses these)."""

from __future__ import annotations

from legdsl.check.control_words import describe_type
from legdsl.ir import controller as ir
from legdsl.ir.controller import ONE, Type
from legdsl.lang import ast
from legdsl.lang.turning import FREQUENCY
from legdsl.lang.units import KINDS, Dim, describe


def unit_of(dim: Dim) -> str:
    """The unit a dimension is written in: its kind's ('deg', 'm/s'), else its base units."""
    word = describe(dim)
    return next((u for d, u in KINDS.values() if d == dim), word.split("(")[-1].rstrip(")"))


def _bare(e: ast.Expr) -> tuple[str, ast.EQuantity] | None:
    """A number written without a unit, possibly negated: its text and the number."""
    sign = ""
    while isinstance(e, ast.EUnary) and e.op == "-":
        sign, e = "-" if not sign else "", e.operand
    if isinstance(e, ast.EQuantity) and e.quantity.unitless:
        return sign + e.text, e
    return None


def mismatch_hint(values: list[ir.Expr], exprs: list[ast.Expr]) -> str:
    """What to write where values that must have one dimension do not: a number written
    without its unit, Hz for a turning rate, or what turns one dimension into the other."""
    bare = [(i, b[0]) for i, b in enumerate(_bare(e) for e in exprs) if b is not None]
    bare_at = {i for i, _ in bare}
    others = {v.type for i, v in enumerate(values) if i not in bare_at and v.type is not None}
    if len(bare) == 1 and len(others) == 1:
        (dim,) = others
        if isinstance(dim, tuple) and dim != ONE:
            return f"; write the number with its unit, as in '{bare[0][1]} {unit_of(dim)}'"
    dims = list(dict.fromkeys(v.type for v in values if isinstance(v.type, tuple)))
    if len(dims) != 2:
        return "; write them all in units of one dimension"
    if set(dims) == {ir.ANGULAR_VELOCITY, FREQUENCY}:
        return (
            "; Hz counts cycles per second, with no angle in it: write a turning rate as an "
            "angle per second, 1 Hz being '1 rev/s' (= '360 deg/s' = '2 * pi * 1 rad/s')"
        )
    first, second = dims
    ratio = (
        first[0] - second[0], first[1] - second[1], first[2] - second[2], first[3] - second[3]
    )  # fmt: skip
    if ONE in dims:  # a plain number beside a quantity: it lacks the unit
        quantity = second if first == ONE else first
        return f"; give the plain number a unit of {describe(quantity)}, as in '* 1 {unit_of(quantity)}'"
    if all(d != ratio for d, _ in KINDS.values()):  # nothing simple relates them
        return (
            f"; write like with like, both in {unit_of(first)} or both in {unit_of(second)}: "
            "one of them is not the value meant"
        )
    return (
        f"; {describe_type(second)} times {describe_type(ratio)} (as '1 {unit_of(ratio)}') "
        f"makes {describe_type(first)}: multiply by what relates them, or write like with like"
    )


def sqrt_hint(arg: ast.Expr, t: Dim) -> str:
    """sqrt() of a quantity whose powers are not all even: take it of a plain number."""
    text = _text(arg)
    return (
        f"; take it of a plain number, as in 'sqrt({text} / (1 {unit_of(t)}))', or of a square, "
        "as in 'sqrt(x ^ 2)'"
    )


def want_hint(func: str, arg: ast.Expr, what: str, t: Type) -> str:
    """``func`` takes ``what`` (an angle, a plain number), given ``t``: divide by its unit,
    or for an angle, turn it into one."""
    if not isinstance(t, tuple) or t == ONE:
        return ""
    text, unit = _text(arg), unit_of(t)
    plain = f"'{func}({text} / (1 {unit}))'"
    if what == "an angle":  # a plain number is read as radians
        return f"; make it an angle or a plain number (read as radians), as in {plain}"
    return f"; make it a plain number, as in {plain}"


def _text(e: ast.Expr) -> str:
    if isinstance(e, ast.EName):
        return e.ident.name
    if isinstance(e, ast.EAttr):
        return f"{_text(e.base)}.{e.attr.name}"
    return "x"


def number_member(name: str) -> str:
    example = f", as in 'com.{name}'" if name in ir.COM_MEMBERS else ""
    return (
        f"a number has no member '{name}': members are read of the creature's parts, legs, "
        f"roles, com, terrain and paths{example} (docs/language.md lists each one's)"
    )
