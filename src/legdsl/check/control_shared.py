"""Controllers said once: ``shared NAME { ... }`` parts that controllers ``include``, and
controllers that ``extends`` another.

A part holds inputs, parameters, signals, actions and ``own`` records. ``include gains`` puts the part's
declarations where the ``include`` stands, in the part's order; a controller's own
declaration of a name the part declares (of the same kind) gives it another value in the
part's place, so several controllers share their common gains and state only what differs.
Two included parts may not declare one name, nor may one part declare a name twice.

``controller pace extends trot { ... }`` starts from trot's items (its includes too) and puts
each of its own declarations, roles, start, table and actions in the place of trot's of the
same name (or kind), the rest after them; so pace states only what differs, and the order of
its inputs and parameters, which run.json and the generated code follow, stays trot's.
"""

from __future__ import annotations

import dataclasses
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
            if isinstance(item, ast.OwnDecl):
                continue  # names records, which the controller checks
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
                if isinstance(shared, ast.ActionDef | ast.OwnDecl):
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


def _key(item: ast.ControllerItem) -> tuple[str, ...]:
    """What an item of a derived controller replaces in its base: the same kind and name."""
    if isinstance(item, Declared):
        return ("declared", item.name.name)
    if isinstance(item, ast.ActionDef | ast.PathDecl):
        return (type(item).__name__, item.name.name)
    if isinstance(item, ast.IncludeDecl):
        return ("include", *(n.name for n in item.names))
    if isinstance(item, ast.OwnDecl):
        return ("own", *(n.name for n in item.names))
    return (type(item).__name__,)  # roles, start, table: one each


def extend_bases(
    decls: Iterable[ast.ControllerDecl], diag: Diagnostics
) -> list[ast.ControllerDecl]:
    """The controllers with every ``extends`` resolved (bases first, chains followed); one
    that extends an unknown controller, or itself through a chain, is reported and left out."""
    written = list(decls)
    by_name = {d.name.name: d for d in written}
    done: dict[str, ast.ControllerDecl | None] = {}

    def resolve(decl: ast.ControllerDecl, chain: tuple[str, ...]) -> ast.ControllerDecl | None:
        name = decl.name.name
        if name in done:
            return done[name]
        if decl.base is None:
            done[name] = decl
            return decl
        base_name = decl.base.name
        if base_name == name or base_name in chain:
            loop = (*chain[chain.index(base_name) :], name) if base_name in chain else (name,)
            diag.error(
                decl.base.span,
                f"controller '{name}' extends itself ({' -> '.join((*loop, base_name))}); "
                "break the loop: one of them must extend none of the others",
            )
            done[name] = None
            return None
        written_base = by_name.get(base_name)
        if written_base is None:
            diag.error(
                decl.base.span,
                f"unknown controller '{base_name}' to extend; write 'controller {base_name} "
                f"{{ ... }}' in this file{did_you_mean(base_name, by_name)}",
            )
            done[name] = None
            return None
        base = resolve(written_base, (*chain, name))
        done[name] = None if base is None else _merged(decl, base, diag)
        return done[name]

    resolved = [resolve(d, ()) for d in written]
    return [d for d in resolved if d is not None]


def _merged(
    decl: ast.ControllerDecl, base: ast.ControllerDecl, diag: Diagnostics
) -> ast.ControllerDecl:
    own: dict[tuple[str, ...], ast.ControllerItem] = {}
    for item in decl.items:
        own.setdefault(_key(item), item)  # a second one is 'defined twice' later
    used: set[int] = set()
    items: list[ast.ControllerItem] = []
    for item in base.items:
        override = own.get(_key(item))
        if override is None:
            items.append(item)
            continue
        used.add(id(override))
        if (
            isinstance(item, Declared)
            and isinstance(override, Declared)
            and (type(override) is not type(item))
        ):
            diag.error(
                override.name.span,
                f"'{item.name.name}' is {_ARTICLED[type(item)]} in controller "
                f"'{base.name.name}'; give it another value with "
                f"'{_WORDS[type(item)]} {item.name.name} = ...'",
            )
            items.append(item)
            continue
        items.append(override)
    items += [item for item in decl.items if id(item) not in used]
    creature = decl.creature if decl.creature is not None else base.creature
    return dataclasses.replace(decl, creature=creature, items=tuple(items))
