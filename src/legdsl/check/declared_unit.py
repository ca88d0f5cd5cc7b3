"""An input or parameter declared in the wrong unit, told at its declaration, where the fix
goes: ``param jump_k = 200 N*m`` (N*m/rad meant), then ``ankle_spring.k = select(c, jump_k,
ankle_k)``, was told at the select() with "multiply by an angle", and ``input jump_height =
0.3 s`` at a select() beside ``terrain.ahead_height`` with "times a velocity makes a length".

Where the values that must have one dimension (and what is ``needed`` of them) are all of one
dimension but for one input or parameter read as itself, and no number is written beside
it there, that one's declared unit explains the mistake: the error is at its declaration's value, naming the use and the unit to declare
it in (``plain_declared`` does the same for one declared with no unit at all). Two or more
declared names, or a plain number among the others, are not blamed on one declaration.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence

from legdsl.check.control_words import describe_type
from legdsl.check.plain_declared import advice, lone_declared, number_text
from legdsl.ir import controller as ir
from legdsl.lang import ast
from legdsl.lang.errors import Span

# input or parameter -> its kind ('input' or 'param') and the value it is declared with
Declared = Mapping[str, tuple[str, ast.Expr]]


def declared_unit(
    declared: Declared,
    values: Sequence[ir.Expr],
    used_at: Span,
    what: str,
    needed: ir.Type = None,
    written: Sequence[ast.Expr] = (),
) -> tuple[Span, str] | None:
    """The error at the declaration of the one input or parameter among ``values`` whose
    dimension differs from the one the others (and ``needed``) all have, used at ``used_at``
    as ``what`` says; None where no single declaration explains it, or where a number is
    ``written`` beside it at the use (``w > 1 Hz``: that number may be the mistake)."""
    if any(_number_of(e) is not None for e in written):
        return None
    found = lone_declared(declared, values, needed)
    if found is None:
        return None
    culprit, want = found
    if not isinstance(culprit.type, tuple) or culprit.type == want:
        return None
    kind, value = declared[culprit.name]
    word = "parameter" if kind == "param" else kind
    at = str(used_at) if used_at.file != value.span.file else f"{used_at.line}:{used_at.col}"
    return (
        value.span,
        f"{word} '{culprit.name}' is declared as {describe_type(culprit.type)}, but it is used "
        f"as {describe_type(want)} at {at}{used_at.within} ({what}); declare it in "
        f"that unit, {advice(kind, culprit.name, _number_of(value), want, 'in')}, or, if "
        "another value was meant there, write that one",
    )


NUMBER = re.compile(r"[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?")


def _number_of(value: ast.Expr) -> str | None:
    """The number a declaration's value is written with, without its unit ('200' of '200
    N*m'); None if it is not a number."""
    text = number_text(value)
    if text is None:
        return None
    sign = text[: len(text) - len(text.lstrip("-"))]
    found = NUMBER.match(text.lstrip("-").strip())
    return sign + found.group(0) if found else None
