"""The tuned ``.leg`` file ``legdsl tune`` writes: the input with only the tuned values
changed, each in the unit it was written in and with the digits that read back the very value
the tune ran; a parameter the controller takes from another (the controller it ``extends``,
a shared part in another file) declared anew in it, so that the other keeps its value; one a
controller extending the tuned one takes from it declared anew there with its old value."""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

from legdsl.check.values import written_unit as written_unit_of
from legdsl.files import write_atomic
from legdsl.ir.controller import Controller
from legdsl.lang import ast
from legdsl.lang.errors import UsageError
from legdsl.lang.parser import parse_file
from legdsl.lang.scaling import moved_use
from legdsl.lang.units import parse_unit


def write_tuned(
    source: Path,
    controller: Controller,
    values: dict[str, float],
    out: Path,
    others: Sequence[Controller] = (),
) -> Path:
    """The ``.leg`` file with only the tuned parameters' values changed (in their own units).
    Of the file's ``others`` controllers, one that ``extends`` the tuned one and takes a tuned
    parameter from it gets the parameter's old value declared anew, so that it keeps it."""
    tree, text = parse_file(source)
    spans = declared_in(source, controller, values)
    edits = []
    # declarations added to a controller (by its span): the tuned one's own, and the old
    # values of those that extend it
    added: dict[Any, list[str]] = {controller.span: []}
    found = set()
    own = _declaration(tree, controller)
    # a parameter is declared by the controller, a controller it extends, or a shared part
    declared: list[tuple[object, ast.ControllerItem | ast.SharedItem]] = [
        (decl, item) for decl in tree.controllers for item in decl.items
    ] + [(part, item) for part in tree.shared for item in part.items]
    for name, span in spans.items():  # declared in another file: overridden here
        if span.file != str(source):
            added[controller.span].append(
                f"param {name} = {_value_edit(_param_decl(span), values[name])[3]}"
            )
            found.add(name)
    for decl, item in declared:
        if isinstance(item, ast.ParamDecl) and item.name.span in spans.values():
            line, col, end, new = _value_edit(item, values[item.name.name])
            if isinstance(decl, ast.ControllerDecl) and decl is not own and own is not None:
                # declared by the controller it extends: overridden in the tuned one, so the
                # other controller keeps its value
                added[controller.span].append(f"param {item.name.name} = {new}")
            else:
                edits.append((line, col, end, new))
            found.add(item.name.name)
    if missing := sorted(set(spans) - found):
        raise UsageError(f"cannot find where {', '.join(missing)} is declared in {source}")
    for span, kept in _kept_by_extenders(tree, controller, others, spans).items():
        added.setdefault(span, []).extend(kept)
    lines = text.split("\n")
    edits += _uses_moved(tree, lines, source, out)
    for line, col, end, new in sorted(edits, reverse=True):  # no line added yet: in place
        row = lines[line - 1]
        rest = row[end - 1 :]
        if rest.lstrip().startswith("#"):  # keep a comment's column where there is room
            gap = len(rest) - len(rest.lstrip()) - (len(new) - (end - col))
            rest = " " * max(1, gap) + rest.lstrip()
        lines[line - 1] = row[: col - 1] + new + rest
    if own is not None:  # as the tree has it
        added[own.span] = added.pop(controller.span)
    bodies = [d for d in tree.controllers if added.get(d.span)]
    for decl in sorted(bodies, key=lambda d: (d.span.line, d.span.col), reverse=True):
        lines = _declared_first(lines, decl, added[decl.span])  # from the end: lines move
    write_atomic(out, "\n".join(lines))
    return out


def _kept_by_extenders(
    tree: ast.SourceFile,
    controller: Controller,
    others: Sequence[Controller],
    spans: dict[str, Any],
) -> dict[str, list[str]]:
    """The declarations that keep the old values of the tuned parameters in each controller
    of the file that ``extends`` the tuned one and takes them from it (it was retuned too,
    unsaid): by the controller's span. Its own extenders then take them from it."""
    old = {c.name: c for c in controller.params}
    own = _declaration(tree, controller)
    children = {d.span for d in tree.controllers if own is not None and _base_in(tree, d) is own}
    kept: dict[Any, list[str]] = {}
    for other in others:
        if other.span not in children:
            continue
        for p in other.params:  # the same declaration as the tuned one's: it takes it
            if p.name in spans and p.span == old[p.name].span:
                text = _value_edit(_param_decl(p.span), old[p.name].value)[3]
                kept.setdefault(other.span, []).append(f"param {p.name} = {text}")
    return kept


def _base_in(tree: ast.SourceFile, decl: ast.ControllerDecl) -> ast.ControllerDecl | None:
    """The controller of ``tree`` that ``decl`` extends, as the checker resolves it (another
    of the base's name in the file; with several, the one for ``decl``'s creature), or None:
    it extends none, or one of a used file. ``controller trot extends trot`` extends the used
    file's trot, not itself: taken for its own extender, the tuned trot got the old values of
    the tuned parameters declared next to the new ones ('leg_k' is defined twice)."""
    if decl.base is None:
        return None
    named = [c for c in tree.controllers if c.name.name == decl.base.name and c is not decl]
    if decl.creature is not None:
        mine = [
            c for c in named if c.creature is not None and c.creature.name == decl.creature.name
        ]
        named = mine or named
    return named[0] if named else None


def _declaration(tree: ast.SourceFile, controller: Controller) -> ast.ControllerDecl | None:
    """The tuned controller's declaration in the file: by its place, as two creatures' may
    share a name (``controller hop for heavy``: the first 'hop' was taken, the other
    creature's, and the tuned file declared kp twice in both)."""
    named = [d for d in tree.controllers if d.name.name == controller.name]
    return next(
        (d for d in named if d.span == controller.span), named[0] if len(named) == 1 else None
    )


def _declared_first(lines: list[str], decl: ast.ControllerDecl, added: list[str]) -> list[str]:
    """``lines`` with the ``added`` declarations first in ``decl``'s body."""
    if not _first_item_on_own_line(decl):
        return _open_body(lines, decl, added)
    first = decl.items[0].span
    indent = lines[first.line - 1][: first.col - 1]
    return lines[: first.line - 1] + [indent + a for a in added] + lines[first.line - 1 :]


def _first_item_on_own_line(own: ast.ControllerDecl) -> bool:
    return bool(own.items) and own.items[0].span.line > own.span.line


def _open_body(lines: list[str], own: ast.ControllerDecl, overrides: list[str]) -> list[str]:
    """``lines`` with ``overrides`` on lines of their own just after the ``{`` of ``own``'s
    body: an empty body (``{`` then ``}``) or one written on the controller's line has no
    item line to put them before."""
    line = own.span.line - 1
    while "{" not in lines[line][own.span.col - 1 if line == own.span.line - 1 else 0 :]:
        line += 1
    row = lines[line]
    brace = row.index("{", own.span.col - 1 if line == own.span.line - 1 else 0)
    outer = row[: len(row) - len(row.lstrip())]
    indent = outer + "  "
    rest = row[brace + 1 :].strip()
    closing = outer if rest.startswith("}") else indent  # '{ }': the brace under 'controller'
    body = [indent + o for o in overrides] + ([closing + rest] if rest else [])
    return lines[:line] + [row[: brace + 1]] + body + lines[line + 1 :]


def _uses_moved(
    tree: ast.SourceFile, lines: list[str], source: Path, out: Path
) -> list[tuple[int, int, int, str]]:
    """Edits pointing each ``use "path"`` at the same file from ``out``'s folder: a path is
    relative to the file that says it, so the tuned file elsewhere would lose the shared parts
    and actions it uses (the standard library's, named bare, stay)."""
    edits = []
    for use in tree.uses:
        moved = moved_use(use, source, out)
        row = lines[use.span.line - 1]
        quote = row.find('"', use.span.col - 1)
        if moved is not None and quote >= 0:
            end = quote + len(use.target) + 2  # past the closing quote
            edits.append((use.span.line, quote + 1, end + 1, f'"{moved}"'))
    return edits


def declared_in(source: Path, controller: Controller, names: Iterable[str]) -> dict[str, Any]:
    """Where each named parameter is declared. One declared in another file (a shared part
    or a controller it uses) is overridden in the tuned controller, which must then be
    declared in ``source`` itself, else a ``UsageError`` (checked before a tune)."""
    names = set(names)
    spans = {}
    for c in controller.params:
        if c.name in names:
            if c.span.file != str(source) and controller.span.file != str(source):
                used = os.path.normpath(c.span.file)  # without its "outside/../.."
                raise UsageError(
                    f"controller '{controller.name}' and its '{c.name}' are declared in {used}, "
                    f"not in {source}: tune a controller of {source} (one that extends "
                    f"'{controller.name}' will do)"
                )
            spans[c.name] = c.span
    return spans


def used_owners(source: Path, spans: dict[str, Any]) -> dict[str, str]:
    """Of the parameters declared at ``spans`` (``declared_in``), those declared in another
    file, with its path: the tuned file overrides them in the tuned controller."""
    return {
        name: os.path.normpath(span.file)
        for name, span in spans.items()
        if span.file != str(source)
    }


def shared_owners(source: Path, spans: dict[str, Any]) -> dict[str, str]:
    """Of the parameters declared at ``spans`` (``declared_in``), those declared in a shared
    part of ``source``, with its name: the tuned file changes them for every controller that
    includes the part."""
    tree, _ = parse_file(source)
    return {
        item.name.name: part.name.name
        for part in tree.shared
        for item in part.items
        if isinstance(item, ast.ParamDecl) and spans.get(item.name.name) == item.name.span
    }


def written_unit(source: Path, controller: Controller, name: str) -> str | None:
    """The unit the file writes parameter ``name`` in ("cm" for ``param stroke = 1.5 cm``,
    "" for a bare number), or None where it is not declared (wherever it is declared)."""
    span = next((c.span for c in controller.params if c.name == name), None)
    item = _param_decl(span) if span is not None else None
    if item is None:
        return None
    node = item.value
    while isinstance(node, ast.EUnary) and node.op == "-":
        node = node.operand
    return written_unit_of(node.text).replace(" ", "") if isinstance(node, ast.EQuantity) else None


def _param_decl(span: Any) -> Any:
    """The parameter declaration named at ``span``, in whichever file it is (None if none)."""
    tree, _ = parse_file(Path(span.file))
    items = [i for d in tree.controllers for i in d.items] + [
        i for part in tree.shared for i in part.items
    ]
    return next((i for i in items if isinstance(i, ast.ParamDecl) and i.name.span == span), None)


def _value_edit(item: ast.ParamDecl, si: float) -> tuple[int, int, int, str]:
    """(line, column, end column, new text) of a parameter's value, kept in its unit."""
    node = item.value
    while isinstance(node, ast.EUnary) and node.op == "-":
        node = node.operand
    assert isinstance(node, ast.EQuantity)
    _, _, unit = node.text.partition(" ")
    factor = parse_unit(unit.replace(" ", ""))[0] if unit else 1.0  # SI per written unit
    new = _exact_text(si, factor) + (f" {unit}" if unit else "")
    span = item.value.span  # the whole value, a leading '-' too
    return span.line, span.col, span.end_col, new


def _exact_text(si: float, factor: float) -> str:
    """The shortest number that, read back as the parser does (``float(text) * factor``), is
    ``si`` exactly: rounded (to 6 digits, say), the tuned file ran another gait than the tune's
    best, and a fall where the tune measured none is no rare thing for a legged gait."""
    written = si / factor
    near, below, above = [written], written, written
    for _ in range(4):  # where written * factor misses si by an ulp, a neighbour hits it
        below, above = math.nextafter(below, -math.inf), math.nextafter(above, math.inf)
        near += [below, above]
    texts = [_shortest(x) for x in near if x * factor == si]
    return min(texts, key=len) if texts else _shortest(written)  # else the nearest


def _shortest(x: float) -> str:
    """The shortest text that reads back as ``x`` (510, not 510.0)."""
    text = repr(x)
    return text[:-2] if text.endswith(".0") else text
