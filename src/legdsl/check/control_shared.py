"""Shared controller parts: ``shared NAME { ... }`` blocks that controllers ``include``.

A part holds inputs, parameters, signals and actions. ``include gains`` puts the part's
declarations where the ``include`` stands, in the part's order; a controller's own
declaration of a name the part declares (of the same kind) gives it another value in the
part's place, so several controllers share their common gains and state only what differs.
Two included parts may not declare one name, nor may one part declare a name twice.
"""

from __future__ import annotations

from collections.abc import Iterable

from legdsl.check.values import did_you_mean
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostics, Span

Declared = ast.InputDecl | ast.ParamDecl | ast.SignalDecl
_WORDS: dict[type, str] = {ast.InputDecl: "input", ast.ParamDecl: "param", ast.SignalDecl: "signal"}
_ARTICLED: dict[type, str] = {
    ast.InputDecl: "an input",
    ast.ParamDecl: "a parameter",
    ast.SignalDecl: "a signal",
}


def shared_parts(parts: Iterable[ast.SharedDecl], diag: Diagnostics) -> dict[str, ast.SharedDecl]:
    """The parts by name (a nearer file's part replaces a used file's); each checked once for
    names it declares twice."""
    found: dict[str, ast.SharedDecl] = {}
    for part in parts:
        prior = found.get(part.name.name)
        if prior is not None and prior.span.file == part.span.file:
            diag.error(
                part.name.span,
                f"shared part '{part.name.name}' is defined twice (first at {prior.name.span})",
            )
            continue
        seen: dict[str, Span] = {}
        for item in part.items:
            name = item.name
            if name.name in seen:
                diag.error(
                    name.span,
                    f"'{name.name}' is declared twice in shared part '{part.name.name}' "
                    f"(first at {seen[name.name]})",
                )
            seen[name.name] = name.span
        found[part.name.name] = part
    return found


def expand_includes(
    decl: ast.ControllerDecl, parts: dict[str, ast.SharedDecl], diag: Diagnostics
) -> tuple[ast.ControllerItem, ...]:
    """The controller's items with each ``include`` replaced by the parts' declarations, and
    the controller's own declarations of those names moved into the parts' places."""
    included: dict[str, tuple[str, Declared]] = {}  # name -> (part, its declaration there)
    items: list[ast.ControllerItem] = []
    for item in decl.items:
        if not isinstance(item, ast.IncludeDecl):
            items.append(item)
            continue
        for ident in item.names:
            part = parts.get(ident.name)
            if part is None:
                diag.error(
                    ident.span,
                    f"unknown shared part '{ident.name}'; define it with 'shared "
                    f"{ident.name} {{ ... }}' or 'use' a file that has it"
                    f"{did_you_mean(ident.name, parts)}",
                )
                continue
            for shared in part.items:
                if isinstance(shared, ast.ActionDef):
                    items.append(shared)
                    continue
                other = included.get(shared.name.name)
                if other is not None and other[0] == part.name.name:
                    continue  # declared twice in the part: reported with the part
                if other is not None:
                    diag.error(
                        ident.span,
                        f"'{shared.name.name}' is declared by both shared parts '{other[0]}' "
                        f"and '{part.name.name}'; include one of them, or rename it in one",
                    )
                    continue
                included[shared.name.name] = (part.name.name, shared)
                items.append(shared)
    own: dict[str, Declared] = {}  # the controller's own declarations of included names
    for item in decl.items:
        if isinstance(item, Declared) and item.name.name in included:
            own.setdefault(item.name.name, item)  # a second one is 'defined twice' later
    moved = {id(item) for item in own.values()}
    out: list[ast.ControllerItem] = []
    for item in items:
        if id(item) in moved:
            continue  # moved into the part's place below
        if isinstance(item, Declared) and item.name.name in own:
            override = own[item.name.name]
            if type(override) is not type(item):
                diag.error(
                    override.name.span,
                    f"'{item.name.name}' is {_ARTICLED[type(item)]} in shared part "
                    f"'{included[item.name.name][0]}'; give it another value with "
                    f"'{_WORDS[type(item)]} {item.name.name} = ...'",
                )
                out.append(item)
                continue
            out.append(override)
            continue
        out.append(item)
    return tuple(out)
