"""What a controller's text reads, found in one walk before it is checked: each name read
with a member (``route.lateral``: a path's, ``trunk.yaw``: a body's) and the names its lets
give, so that an unknown name is told with the declaration its use asks for
(``NameResolver.unknown_name``); and the names a table's actions record."""

from __future__ import annotations

import functools
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import fields, is_dataclass
from typing import Any

from legdsl.lang import ast
from legdsl.lang.errors import Span


def dotted_members(
    node: Any, found: dict[str, set[str]] | None = None, lets: dict[str, Span] | None = None
) -> dict[str, set[str]]:
    """Each name read with a member in ``node`` (``trunk.yaw``, ``route.lateral``), and its
    members; ``lets`` gets each name a ``let`` gives, and where (the first)."""
    found = {} if found is None else found
    if lets is not None and isinstance(node, ast.LetStmt):
        lets.setdefault(node.name.name, node.name.span)
    if isinstance(node, ast.EAttr) and isinstance(node.base, ast.EName):
        found.setdefault(node.base.ident.name, set()).add(node.attr.name)
    if isinstance(node, tuple) and len(node) > 1 and all(isinstance(i, ast.Ident) for i in node):
        found.setdefault(node[0].name, set()).add(node[1].name)  # a target: trunk.x = ...
    if isinstance(node, tuple | list):
        for item in node:
            dotted_members(item, found, lets)
    else:
        for name in _walked_fields(node.__class__):
            dotted_members(getattr(node, name), found, lets)
    return found


def given(
    actions: Mapping[str, ast.ActionDef], call: ast.InvokeStmt | None, name: str
) -> tuple[str, set[str]] | None:
    """The action ``call`` calls and the members it reads of ``name`` where the call gives
    it as a plain name (``trunk`` to ``place_foot_3d(leg, body, ...)``: a body's,
    ``body.yaw``); None when it is not an argument of ``call``."""
    if call is None:
        return None
    places = [
        i for i, a in enumerate(call.args) if isinstance(a, ast.EName) and a.ident.name == name
    ]
    if not places:
        return None
    read = set().union(*(_parameter_members(actions, call.action.name, i) for i in places))
    return call.action.name, read


def _parameter_members(
    actions: Mapping[str, ast.ActionDef],
    action: str,
    index: int,
    seen: frozenset[int] = frozenset(),
) -> set[str]:
    """The members read of ``action``'s parameter at ``index``, in its statements and in
    the actions it passes the parameter on to."""
    found = actions.get(action)
    if not isinstance(found, ast.ActionDef) or index >= len(found.params) or id(found) in seen:
        return set()
    name = found.params[index].name
    members = set(dotted_members(found.body).get(name, ()))
    for call in _invokes(found.body):
        for i, arg in enumerate(call.args):
            if isinstance(arg, ast.EName) and arg.ident.name == name:
                members |= _parameter_members(actions, call.action.name, i, seen | {id(found)})
    return members


def _invokes(node: Any) -> Iterator[ast.InvokeStmt]:
    if isinstance(node, ast.InvokeStmt):
        yield node
    elif isinstance(node, tuple | list):
        for item in node:
            yield from _invokes(item)
    else:
        for field in _walked_fields(node.__class__):
            yield from _invokes(getattr(node, field))


def reads_of(node: Any, name: str, found: list[Span] | None = None) -> list[Span]:
    """Where ``node`` reads ``name`` (each plain use of it, in the order written)."""
    found = [] if found is None else found
    if isinstance(node, ast.EName):
        if node.ident.name == name:
            found.append(node.span)
    elif isinstance(node, tuple | list):
        for item in node:
            reads_of(item, name, found)
    else:
        for field in _walked_fields(node.__class__):
            reads_of(getattr(node, field), name, found)
    return found


@functools.cache
def _walked_fields(cls: type) -> tuple[str, ...]:
    """The fields ``dotted_members`` walks into, per class (``fields`` is slow to ask each
    node: this walk visits every node of every controller)."""
    if not is_dataclass(cls) or issubclass(cls, Span):
        return ()
    return tuple(f.name for f in fields(cls))


def unreached_recorders(
    actions: dict[str, ast.ActionDef], reachable: set[str]
) -> dict[str, tuple[str, ...]]:
    """Record -> the actions not in ``reachable`` that record it, in the order defined."""
    found: dict[str, tuple[str, ...]] = {}
    for name, action in actions.items():
        if name not in reachable:
            for record in collect_records([], [action]):
                found[record] = (*found.get(record, ()), name)
    return found


def collect_records(
    tables: list[ast.TableDecl], actions: Iterable[ast.ActionDef]
) -> dict[str, Span]:
    """The names recorded in the table's rows and in these actions' bodies, in that order."""
    found: dict[str, Span] = {}

    def walk(stmts: tuple[ast.Stmt, ...]) -> None:
        for s in stmts:
            if isinstance(s, ast.RecordStmt):
                found.setdefault(s.name.name, s.name.span)
            elif isinstance(s, ast.EachStmt):
                walk(s.body)

    for t in tables:
        for row in t.rows:
            walk(row.actions)
    for action in actions:
        walk(action.body)
    return found
