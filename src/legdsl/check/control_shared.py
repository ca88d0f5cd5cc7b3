"""Controllers said once: ``shared NAME { ... }`` parts that controllers ``include``, and
controllers that ``extends`` another.

A part holds anything a controller holds (declarations, actions, roles, paths, a start, a
table, ``own`` lines) and includes of other parts. ``include gains`` puts the part's
declarations where the ``include`` stands, in the part's order; a controller's own
declaration of a name the part declares (of the same kind) gives it another value in the
part's place, so several controllers share their common gains and state only what differs;
its own action replaces the part's of that name. Two included parts may not declare one name,
nor may one part declare a name twice.

``controller pace extends trot { ... }`` starts from trot's items (its includes too) and puts
each of its own declarations, roles, start, table and actions in the place of trot's of the
same name (or kind), the rest after them; so pace states only what differs, and the order of
its inputs and parameters, which run.json and the generated code follow, stays trot's. The
parts pace includes are its own text too: they replace trot's items of their names (in the
include's place), and pace's own items replace theirs (an action too, where trot took it
from a part).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from legdsl.check.templates import respan
from legdsl.check.used_controllers import Tie, UsedControllers
from legdsl.check.values import defined_by_both, did_you_mean
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostics, Span

Declared = ast.InputDecl | ast.ParamDecl | ast.SignalDecl
_WORDS: dict[type, str] = {ast.InputDecl: "input", ast.ParamDecl: "param", ast.SignalDecl: "signal"}


@dataclass(frozen=True)
class Extension:
    """A derived controller's own declarations against its base's (``check.derived``)."""

    base: str  # the base's name
    replaced: tuple[tuple[Declared, Declared], ...]  # (its own, the base's of that name)
    added: tuple[Declared, ...]  # its own, of names the base does not declare
    inherited: tuple[Declared, ...]  # the base's (its parts' too)


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
            if not isinstance(item, Declared | ast.ActionDef):
                continue  # roles, a table, a path, includes: a second one is reported in use
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
    """The controller's items with each ``include`` replaced by the parts' items (a part's own
    includes expanded first), and the controller's own items of the same name and kind moved
    into the parts' places."""
    items, source = _expanded(decl.items, parts, diag, ())
    # a part's table (or roles...) is checked against each includer's names: say whose
    return tuple(
        respan(item, f" (in controller '{decl.name.name}', from shared part '{source[id(item)]}')")
        if id(item) in source and not isinstance(item, ast.InputDecl | ast.ParamDecl)
        else item
        for item in items
    )


def _expanded(
    written: tuple[ast.ControllerItem, ...],
    parts: dict[str, ast.SharedDecl],
    diag: Diagnostics,
    chain: tuple[str, ...],
) -> tuple[tuple[ast.ControllerItem, ...], dict[int, str]]:
    """The items expanded, and the part each one that is not an action came from."""
    included: dict[tuple[str, ...], tuple[str, ast.ControllerItem]] = {}  # key -> (part, item)
    part_actions: set[int] = set()  # the actions the parts bring
    items: list[ast.ControllerItem] = []
    for item in written:
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
            if isinstance(part, ast.AmbiguousShared):
                what = f"shared part '{ident.name}'"
                diag.error(ident.span, defined_by_both(what, part.files, part.distance))
                continue
            if ident.name in chain:
                loop = " -> ".join((*chain[chain.index(ident.name) :], ident.name))
                diag.error(
                    ident.span,
                    f"shared part '{ident.name}' includes itself ({loop}); break the loop: "
                    "one of them must include none of the others",
                )
                continue
            for shared in _expanded(part.items, parts, diag, (*chain, ident.name))[0]:
                if isinstance(shared, ast.ActionDef | ast.OwnDecl):
                    items.append(shared)  # two of one name: 'defined twice' later
                    if isinstance(shared, ast.ActionDef):
                        part_actions.add(id(shared))
                    continue
                key = _key(shared)
                other = included.get(key)
                if other is not None and other[1] is shared:
                    continue  # the same part reached twice: its items are already here
                if other is not None and other[0] == part.name.name:
                    if not isinstance(shared, Declared):  # a name twice: reported with the part
                        items.append(shared)  # a second table: 'one table' later
                    continue
                if other is not None:
                    diag.error(ident.span, _both(key, other[0], part.name.name))
                    continue
                included[key] = (part.name.name, shared)
                items.append(shared)
    own: dict[tuple[str, ...], ast.ControllerItem] = {}  # own items replacing included ones
    for item in written:
        if not isinstance(item, ast.IncludeDecl | ast.ActionDef) and _key(item) in included:
            own.setdefault(_key(item), item)  # a second one is 'defined twice' later
    # an own action replaces the parts' of its name, in the (first) part's place
    own_actions: dict[str, ast.ActionDef] = {}
    for item in written:
        if isinstance(item, ast.ActionDef):
            own_actions.setdefault(item.name.name, item)  # a second: 'defined twice' later
    brought = {i.name.name for i in items if isinstance(i, ast.ActionDef) and id(i) in part_actions}
    replacing = {name: action for name, action in own_actions.items() if name in brought}
    moved = {id(item) for item in (*own.values(), *replacing.values())}
    out: list[ast.ControllerItem] = []
    for item in items:
        if isinstance(item, ast.ActionDef) and id(item) in part_actions:
            action = replacing.get(item.name.name)
            if action is not None:
                if all(placed is not action for placed in out):
                    out.append(action)
                continue
        if id(item) in moved:
            continue  # moved into the part's place below
        override = own.get(_key(item)) if not isinstance(item, ast.ActionDef) else None
        if override is None or included.get(_key(item), ("", None))[1] is not item:
            out.append(item)
            continue
        if isinstance(item, Declared) and type(override) is not type(item):
            assert isinstance(override, Declared)
            diag.error(
                override.name.span,
                f"'{item.name.name}' is {_ARTICLED[type(item)]} in shared part "
                f"'{included[_key(item)][0]}'; give it another value with "
                f"'{_WORDS[type(item)]} {item.name.name} = ...'",
            )
            out.append(item)
            continue
        out.append(override)
    return tuple(out), {id(item): part for part, item in included.values()}


def _both(key: tuple[str, ...], first: str, second: str) -> str:
    """Two included parts that both have one item (a name, the roles, a table...)."""
    if key[0] == "declared":
        return (
            f"'{key[1]}' is declared by both shared parts '{first}' and '{second}'; "
            "include one of them, or rename it in one"
        )
    what = {"RolesDecl": "roles", "StartDecl": "a start state", "TableDecl": "a table"}
    thing = f"a path '{key[1]}'" if key[0] == "PathDecl" else what.get(key[0], key[0])
    return (
        f"shared parts '{first}' and '{second}' both have {thing}; include one of them, "
        "or leave it out of one"
    )


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
    decls: Iterable[ast.ControllerDecl],
    diag: Diagnostics,
    parts: dict[str, ast.SharedDecl] | None = None,
    used: UsedControllers | None = None,
    extensions: dict[int, Extension] | None = None,
) -> list[ast.ControllerDecl]:
    """The controllers with every ``extends`` resolved (bases first, chains followed); one
    that extends an unknown controller, or itself through a chain, is reported and left out.
    A derived controller's own items beat the parts it includes, which beat its base's.
    A base not in the controller's own file is the nearest used file's (``used``).
    ``extensions``: filled with each derived controller's ``Extension``, by its id."""
    written = list(decls)
    here = written[0].span.file if written else ""
    # each declaration resolved once, by itself: two of one name (each for its creature, or
    # one defined twice) are two controllers
    done: dict[int, ast.ControllerDecl | None] = {}
    origin: dict[int, str] = {}  # an inherited item -> the controller that wrote it

    def local(file: str) -> dict[str, list[ast.ControllerDecl]]:
        """The controllers of ``file`` by name (two of one name: each for its creature, or
        one 'defined twice' later)."""
        by_name: dict[str, list[ast.ControllerDecl]] = {}
        for d in written if file == here or used is None else used.own(file):
            by_name.setdefault(d.name.name, []).append(d)
        return by_name

    def resolve(
        decl: ast.ControllerDecl, chain: tuple[tuple[str, str], ...]
    ) -> ast.ControllerDecl | None:
        if id(decl) not in done:
            done[id(decl)] = None  # a loop through other files ends here
            done[id(decl)] = resolved(decl, chain)
        return done[id(decl)]

    def resolved(
        decl: ast.ControllerDecl, chain: tuple[tuple[str, str], ...]
    ) -> ast.ControllerDecl | None:
        name = decl.name.name
        if decl.base is None:
            return decl
        file = decl.span.file
        base_name = decl.base.name
        by_name = local(file)
        candidates = [c for c in by_name.get(base_name, []) if c is not decl]
        names = [n for f, n in chain if f == file]
        if (base_name == name and candidates) or (candidates and base_name in names):
            loop = (*names[names.index(base_name) :], name) if base_name in names else (name,)
            diag.error(
                decl.base.span,
                f"controller '{name}' extends itself ({' -> '.join((*loop, base_name))}); "
                "break the loop: one of them must extend none of the others",
            )
            return None
        writer = ""  # the base's file, when it is a used one
        if not candidates and used is not None:
            found = used.find(file, base_name)
            if isinstance(found, Tie):
                what = f"controller '{base_name}' to extend"
                diag.error(decl.base.span, defined_by_both(what, found.files, found.distance))
                return None
            if found:
                candidates = found
                writer = used.name(Path(found[0].span.file).resolve())
        if not candidates and base_name == name:
            diag.error(
                decl.base.span,
                f"controller '{name}' extends itself ({name} -> {name}); extend another "
                "controller, or 'use' a file that has it",
            )
            return None
        if not candidates:
            diag.error(
                decl.base.span,
                f"unknown controller '{base_name}' to extend; write 'controller {base_name} "
                f"{{ ... }}' in this file"
                f"{did_you_mean(base_name, by_name)}",
            )
            return None
        written_base = _base_for(decl, candidates, diag)
        if written_base is None:
            return None
        base = resolve(written_base, (*chain, (file, name)))
        if base is None:
            return None
        given = _included_keys(decl.items, parts or {})
        merged = _merged(decl, base, diag, origin, given, writer)
        if extensions is not None:
            extensions[id(merged)] = _extension(decl, base, parts or {})
        return merged

    resolved_all = [resolve(d, ()) for d in written]
    return [d for d in resolved_all if d is not None]


def _extension(
    decl: ast.ControllerDecl, base: ast.ControllerDecl, parts: dict[str, ast.SharedDecl]
) -> Extension:
    inherited = _declared(base.items, parts)
    by_name = {(type(item), item.name.name): item for item in inherited}
    own = [item for item in decl.items if isinstance(item, Declared)]
    replaced = [(item, by_name[type(item), item.name.name]) for item in own
                if (type(item), item.name.name) in by_name]  # fmt: skip
    names = {item.name.name for item in inherited}
    added = [item for item in own if item.name.name not in names]
    return Extension(base.name.name, tuple(replaced), tuple(added), tuple(inherited))


def _declared(
    items: Iterable[ast.ControllerItem],
    parts: dict[str, ast.SharedDecl],
    seen: frozenset[str] = frozenset(),
) -> list[Declared]:
    """The inputs, parameters and signals ``items`` declare, those of the parts they include
    (and those parts include) too."""
    found: list[Declared] = []
    for item in items:
        if isinstance(item, Declared):
            found.append(item)
        elif isinstance(item, ast.IncludeDecl):
            for ident in item.names:
                part = parts.get(ident.name)
                if isinstance(part, ast.SharedDecl) and ident.name not in seen:
                    found += _declared(part.items, parts, seen | {ident.name})
    return found


def _included_keys(
    items: Iterable[ast.ControllerItem],
    parts: dict[str, ast.SharedDecl],
    seen: frozenset = frozenset(),
) -> set[tuple[str, ...]]:
    """What the parts ``items`` include (and the parts they include) declare: a derived
    controller's includes replace its base's items of these (mistakes are reported later)."""
    keys: set[tuple[str, ...]] = set()
    for item in items:
        if not isinstance(item, ast.IncludeDecl):
            continue
        for ident in item.names:
            part = parts.get(ident.name)
            if part is None or ident.name in seen:
                continue
            keys |= _included_keys(part.items, parts, seen | {ident.name})
            keys |= {_key(i) for i in part.items
                     if not isinstance(i, ast.IncludeDecl | ast.OwnDecl)}  # fmt: skip
    return keys


def _inherited(
    item: ast.ControllerItem,
    decl: ast.ControllerDecl,
    base: ast.ControllerDecl,
    origin: dict[int, str],
    file: str,
) -> ast.ControllerItem:
    """A base's item in ``decl``: a mistake in it (a table, an action checked against
    ``decl``'s names) names ``decl`` and the controller that wrote it (and its file, a
    used one)."""
    if isinstance(item, ast.InputDecl | ast.ParamDecl):
        return item  # the same value everywhere: reported once, with its writer
    # a signal reads the creature, so its mistakes are the extending controller's too
    writer = origin.get(id(item), _writer(decl, base, file))
    moved = respan(item, f" (in controller '{decl.name.name}', from controller {writer})")
    origin[id(moved)] = writer
    return moved


def _writer(decl: ast.ControllerDecl, base: ast.ControllerDecl, file: str) -> str:
    """The base as a mistake taken from it names it: with its creature where that is not
    ``decl``'s (a name ``decl``'s creature lacks is most likely why)."""
    text = f"'{base.name.name}'"
    if base.creature and decl.creature and base.creature.name != decl.creature.name:
        text += f" for creature '{base.creature.name}'"
    return text + (f" of {file}" if file else "")


def _base_for(
    decl: ast.ControllerDecl, candidates: list[ast.ControllerDecl], diag: Diagnostics
) -> ast.ControllerDecl | None:
    """The controller ``decl`` extends among those of its base's name: with several (one per
    creature), the one for ``decl``'s own creature; without ``for``, which one is ambiguous."""
    if decl.creature is not None:
        for c in candidates:
            if c.creature is not None and c.creature.name == decl.creature.name:
                return c
    creatures = {c.creature.name for c in candidates if c.creature is not None}
    if len(creatures) < 2:
        return candidates[0]
    assert decl.base is not None
    diag.error(
        decl.base.span,
        f"creatures {', '.join(sorted(creatures))} each have a controller '{decl.base.name}'; "
        f"say which one to extend with 'controller {decl.name.name} for CREATURE extends "
        f"{decl.base.name}'",
    )
    return None


def _merged(
    decl: ast.ControllerDecl,
    base: ast.ControllerDecl,
    diag: Diagnostics,
    origin: dict[int, str],
    included: set[tuple[str, ...]],
    file: str = "",
) -> ast.ControllerDecl:
    own: dict[tuple[str, ...], ast.ControllerItem] = {}
    for item in decl.items:
        own.setdefault(_key(item), item)  # a second one is 'defined twice' later
    used: set[int] = set()
    items: list[ast.ControllerItem] = []
    for item in base.items:
        override = own.get(_key(item))
        if override is None and _key(item) in included:
            continue  # the derived controller's include gives it, in the include's place
        if override is None:
            items.append(_inherited(item, decl, base, origin, file))
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
    # a used file's controller is extended for this file's creature, never for its own
    creature = decl.creature if decl.creature is not None or file else base.creature
    return dataclasses.replace(decl, creature=creature, items=tuple(items))
