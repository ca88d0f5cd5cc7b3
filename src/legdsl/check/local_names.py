"""The names a controller's rows and actions give for a while: an action's parameters, a
``let`` and an ``each`` variable. ``let time = 3 deg`` made every ``time`` of the row 3 deg,
``let j`` hid the joint ``j``, ``action p(x, x)`` took the last argument for both; a
``param`` of such a name is refused (``controller.define``), and these are the same way.

None may take a built-in name (``time``, ``pi``, ``com``...), and no action lists a
parameter twice. A ``let`` or ``each`` variable may not hide a name of the creature or the
controller, nor a parameter or local given before it (the free root's coordinates excepted). A parameter may: it stands for its
argument (the library's ``leg`` and ``body``, a creature's ``tuck(..., balance)`` passed
its ``param balance``). Only the controller's own file is held to the hiding rules: another
file's actions are written for any creature, whatever it calls its parts.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

from legdsl.check.control_names import KIND_WORDS, Opaque, Value
from legdsl.check.values import article
from legdsl.ir import controller as ir
from legdsl.ir.model import Model
from legdsl.lang import ast
from legdsl.lang.errors import Span

# Names every controller has besides ir.BUILTIN_VALUES, and what they are.
BUILTIN_THINGS = {
    "com": "the creature's centre of mass",
    "terrain": "the terrain ahead of the creature",
}


def builtin_message(name: str) -> str | None:
    """Why ``name`` cannot be given to a controller's own value, if it is a built-in one."""
    if name in ir.BUILTIN_VALUES:
        return (
            f"'{name}' is a built-in value of every controller "
            f"({', '.join(ir.BUILTIN_VALUES)}); choose another name"
        )
    if name in BUILTIN_THINGS:
        return (
            f"'{name}' is a built-in name of every controller ({BUILTIN_THINGS[name]}); "
            "choose another name"
        )
    return None


def with_article(word: str) -> str:
    return f"{article(word)} {word}"


def what_is(value: Value) -> str:
    """'a joint coordinate', 'an actuator', 'a role'... of a name of the creature or controller."""
    if isinstance(value, ir.Legs):
        return "a role" if value.role is not None else "a leg"
    if isinstance(value, ir.Part):
        return with_article(KIND_WORDS.get(value.kind, value.kind))
    if isinstance(value, ir.Named):
        return with_article({"param": "parameter"}.get(value.kind, value.kind))
    return "a name"


def check_local_names(
    controller: str,
    model: Model,
    names: dict[str, Value],
    signals: Iterable[str],
    rows: Iterable[ast.Row],
    actions: Iterable[ast.ActionDef],
    user_file: str,
    err: Callable[[Span, str], None],
) -> None:
    """Tell each parameter, ``let`` and ``each`` variable of ``rows`` and ``actions`` that
    hides a name: ``names`` (the creature's and the controller's, records too) and
    ``signals``. ``controller``: its name, for the messages."""
    signal_names = set(signals)
    # the free root's coordinates (x, z, pitch) come with 'free', not named in the file, and
    # are read only with a member (x.value): a distance is a natural 'let x'
    rooted = {d.name for d in model.dofs if model.joint(d.joint).kind == "free"}

    def hidden(ident: ast.Ident, local: dict[str, Span], what: str) -> bool:
        """Told if ``ident``, given as ``what`` ('the parameter'), hides a name."""
        name = ident.name
        builtin = builtin_message(name)
        if builtin is not None:
            err(ident.span, f"{builtin} for {what}")
            return True
        if ident.span.file != user_file:
            return False
        if name in local:
            err(
                ident.span,
                f"'{name}' is already given at {local[name]}, which {what} would hide; choose "
                "another name",
            )
            return True
        value = names.get(name)
        if name in signal_names:
            owner = f"controller '{controller}' (a signal)"
        elif isinstance(value, ir.Named):
            owner = f"controller '{controller}' ({what_is(value)})"
        elif isinstance(value, ir.Legs) and value.role is not None:
            owner = f"controller '{controller}' (a role)"
        elif isinstance(value, ir.Part) and value.kind == "path":
            owner = f"controller '{controller}' (a path)"
        elif value is not None and not isinstance(value, Opaque) and name not in rooted:
            owner = f"creature '{model.name}' ({what_is(value)})"
        else:
            return False
        err(
            ident.span,
            f"'{name}' is already a name of {owner}, which {what} would hide; choose another name",
        )
        return True

    def walk(stmts: tuple[ast.Stmt, ...], local: dict[str, Span]) -> None:
        local = dict(local)
        for s in stmts:
            if isinstance(s, ast.LetStmt):
                hidden(s.name, local, f"'let {s.name.name}'")
                local[s.name.name] = s.name.span
            elif isinstance(s, ast.EachStmt):
                hidden(s.var, local, f"'each {s.var.name}'")
                walk(s.body, {**local, s.var.name: s.var.span})

    for row in rows:
        walk(row.actions, {})
    for action in actions:
        params: dict[str, Span] = {}
        for p in action.params:
            if p.name in params:
                err(
                    p.span,
                    f"parameter '{p.name}' is listed twice in action '{action.name.name}' "
                    f"(first at {params[p.name]}); give each parameter a name of its own",
                )
                continue
            builtin = builtin_message(p.name)  # a part's name stands for the argument
            if builtin is not None:
                err(p.span, f"{builtin} for the parameter '{p.name}'")
            params[p.name] = p.span
        walk(action.body, params)
