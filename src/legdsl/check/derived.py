"""A derived controller's own declarations checked against its base's.

``controller hop_long extends hop { param ful = 0.85 m }`` misspells hop's ``full``: as
written it is a parameter of its own that nothing reads, and hop's ``full`` keeps its value.
A new input, parameter or signal that nothing reads and whose name is near one of the base's
is therefore an error naming the base's. (One unlike any of the base's is left alone, as an
unread parameter of any controller is.)

``controller hop_soft extends hop { param stroke = 3 deg }`` gives hop's ``stroke``, a length,
in degrees: hop's table, checked against it, failed where hop uses it (in hop's lines, or
a used file's), never at the user's. So a derived controller that fails, with an input or
parameter of another unit than the base's, is checked again with the base's unit for it;
if that leaves fewer mistakes, the declaration is the one told, at its own line, with the
base's unit and the place the base uses it, and the controller is checked as if it had it.
A derived controller that checks clean with its own unit (its own table reads the name as
such) is right.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

from legdsl.check.control_exprs import unit_advice
from legdsl.check.control_scan import reads_of
from legdsl.check.control_shared import Declared, Extension
from legdsl.check.control_words import describe_type
from legdsl.check.values import did_you_mean, place_of
from legdsl.ir import controller as ir
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostic, Diagnostics, Span
from legdsl.lang.units import Dim

# Checks a controller declaration into the IR, its mistakes to the diagnostics given.
Run = Callable[[ast.ControllerDecl, Diagnostics], ir.Controller | None]

_WORDS: dict[type, str] = {ast.InputDecl: "input", ast.ParamDecl: "param", ast.SignalDecl: "signal"}
# what the IR calls a read of each kind of declaration
_READS: dict[str, str] = {
    "input": "input",
    "param": "param",
    "signal": "signal",
    "integral": "input",
}


def check_derived(
    decl: ast.ControllerDecl, ext: Extension | None, diag: Diagnostics, run: Run
) -> ir.Controller | None:
    """``decl`` checked (``run``), its own declarations against its base's (``ext``)."""
    if ext is None:
        return run(decl, diag)
    changed = [
        (own, base)
        for own, base in ext.replaced
        if None not in (_dim(own), _dim(base)) and _dim(own) != _dim(base)
    ]
    trial = diag.trial()
    checked = run(decl, trial)
    if not trial.items:
        _unread(decl, ext, checked, diag)
        return checked
    blamed: list[tuple[Declared, Declared, Diagnostic]] = []
    for own, base in changed:
        again = diag.trial()
        run(_with_values(decl, [(own, base)]), again)
        gone = [d for d in trial.items if d not in again.items]
        if gone and len(again.items) < len(trial.items):
            blamed.append((own, base, min(gone, key=lambda d: d.span)))
    if not blamed:
        diag.items += trial.items
        return checked
    for own, base, use in blamed:
        diag.error(own.value.span, _other_unit(decl, ext, own, base, use))
    return run(_with_values(decl, [(own, base) for own, base, _ in blamed]), diag)


def _other_unit(
    decl: ast.ControllerDecl, ext: Extension, own: Declared, base: Declared, use: Diagnostic
) -> str:
    given, want = _dim(own), _dim(base)
    assert given is not None and want is not None
    name = own.name.name
    advice = unit_advice(want).removeprefix("; ") or "give it no unit"
    used_at = use.span
    if used_at in (own.value.span, own.name.span):  # told at the declaration: say where read
        used_at = _first_read(decl, name) or used_at
    return (
        f"{_WORDS[type(own)]} '{name}' is {describe_type(given)}, but controller '{ext.base}', "
        f"which this one extends, declares it {describe_type(want)} "
        f"('{_written(base.value)}', {place_of(base.name.span)}) and uses it as one "
        f"({place_of(used_at)}); {advice}"
    )


def _first_read(decl: ast.ControllerDecl, name: str) -> Span | None:
    """Where the controller (its base's lines with it) first reads ``name``: in its table,
    else in its actions, signals or the parts it includes."""
    tables = [i for i in decl.items if isinstance(i, ast.TableDecl)]
    rest = [
        i for i in decl.items if not isinstance(i, ast.TableDecl | ast.InputDecl | ast.ParamDecl)
    ]
    for items in (tables, rest):
        found = reads_of(items, name)
        if found:
            return min(found, key=lambda at: (at.file != decl.span.file, at.line, at.col))
    return None


def _unread(
    decl: ast.ControllerDecl, ext: Extension, checked: ir.Controller | None, diag: Diagnostics
) -> None:
    """The error for each new declaration nothing reads whose name is near one of the base's."""
    if checked is None:
        return
    read: set[tuple[str, str]] = set()
    _reads((checked.states, checked.signals), read)
    for own in ext.added:
        word = _WORDS[type(own)]
        if (word, own.name.name) in read:
            continue
        kin = [b for b in ext.inherited if type(b) is type(own)]
        near = did_you_mean(own.name.name, [b.name.name for b in kin])
        if not near:
            continue
        meant = near.removeprefix("; did you mean '").removesuffix("'?")
        diag.error(
            own.name.span,
            f"{word} '{own.name.name}' is declared but never read; did you mean '{meant}' (of "
            f"{ext.base})? As written it is a {_NOUNS[word]} of its own, and {ext.base}'s "
            f"'{meant}' keeps its value; to give that one another, write "
            f"'{word} {meant} = {_written(own.value)}'",
        )


_NOUNS = {"input": "input", "param": "parameter", "signal": "signal"}


def _reads(node: object, found: set[tuple[str, str]]) -> None:
    """The (kind, name) of every input, parameter and signal read in ``node``."""
    stack = [node]
    while stack:
        item = stack.pop()
        if isinstance(item, ir.Named) and item.kind in _READS:
            found.add((_READS[item.kind], item.name))
        elif dataclasses.is_dataclass(item) and not isinstance(item, type):
            stack.extend(getattr(item, f.name) for f in dataclasses.fields(item))
        elif isinstance(item, tuple | list):
            stack.extend(item)


def _dim(item: Declared) -> Dim | None:
    """The unit an input or parameter is written with (None for a signal, or another value)."""
    node = item.value
    while isinstance(node, ast.EUnary) and node.op == "-":
        node = node.operand
    if isinstance(item, ast.SignalDecl) or not isinstance(node, ast.EQuantity):
        return None
    return node.quantity.dim


def _written(e: ast.Expr) -> str:
    """A declaration's value as written: a number with its unit, possibly negated."""
    if isinstance(e, ast.EUnary) and e.op == "-":
        return f"-{_written(e.operand)}"
    return e.text if isinstance(e, ast.EQuantity) else "..."


def _with_values(
    decl: ast.ControllerDecl, pairs: list[tuple[Declared, Declared]]
) -> ast.ControllerDecl:
    """``decl`` with each own declaration of ``pairs`` given the base's value."""
    values = {id(own): base.value for own, base in pairs}
    items: list[ast.ControllerItem] = []
    for item in decl.items:
        if isinstance(item, Declared) and id(item) in values:
            item = dataclasses.replace(item, value=values[id(item)])
        items.append(item)
    return dataclasses.replace(decl, items=tuple(items))
