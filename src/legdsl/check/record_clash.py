"""A record of the table or of an action it calls may not take a name the controller
already has: two values under one name, the record's never read.

A record written in another file's action (the standard library's ``learn_apex`` records
``apex_trim``) is told at the user's own name, which is the one to change: the library's
line is named in the message, not made the place of the mistake.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

from legdsl.check.control_names import Value
from legdsl.check.control_scan import collect_records
from legdsl.check.values import did_you_mean, place_of
from legdsl.ir import controller as ir
from legdsl.lang import ast
from legdsl.lang.errors import Span


def tell_record_clashes(
    records: dict[str, Span],
    names: dict[str, Value],
    declared: dict[str, str],
    own: dict[str, Span],
    called: Iterable[ast.ActionDef],
    at_controller: Span,
    err: Callable[[Span, str], None],
) -> None:
    """Each record named like one of ``names`` or ``declared`` (the controller's inputs,
    parameters and signals, by kind) is an error; the others join ``names``.

    ``own``: where the controller's own names are declared; ``called``: the actions the
    table reaches; ``at_controller``: where a library record that clashes with a name of the
    creature is told.
    """
    for name, span in records.items():
        if name not in declared and name not in names:
            names[name] = ir.Named("record", name, None)
            continue
        kind = declared.get(name) or kind_word(names[name])
        if span.file == at_controller.file:
            advice = " for the record" if name in declared else ""
            err(
                span, f"'record {name}' would hide the {kind} '{name}'; choose another name{advice}"
            )
            continue
        action = next(a for a in called if collect_records([], [a]).get(name) == span)
        err(
            own.get(name, at_controller),
            f"action '{action.name.name}' ({place_of(span)}), which the table calls, records "
            f"'{name}', which would hide the {kind} '{name}': give the {kind} another name",
        )


def kind_word(value: Value) -> str:
    if isinstance(value, ir.Legs):
        return "role" if value.role is not None else "leg"
    if isinstance(value, ir.Part):
        return value.kind
    if isinstance(value, ir.Named):
        return "value"
    return "name"


# What 'own' would do to each kind of declaration, which is no record: nothing.
_NOT_CARRIED = {
    "input": "it starts from its latest command when a controller takes over; '--set "
    "{controller}.{name}=VALUE' gives this controller its own default",
    "parameter": "it is each controller's own already",
    "signal": "it is computed anew every tick from what it reads",
}


def tell_unrecorded_own(
    owned: Iterable[ast.Ident],
    records: dict[str, Span],
    declared: dict[str, str],
    controller: str,
    err: Callable[[Span, str], None],
) -> None:
    """Each name of ``own`` (records that start at 0 when the controller takes over) that
    ``controller`` does not record; ``declared``: its inputs, parameters and signals."""
    for ident in owned:
        name = ident.name
        if name in records:
            continue
        kind = declared.get(name)
        if kind is not None:  # recording it would hide it ('record w' is refused)
            why = _NOT_CARRIED[kind].format(controller=controller, name=name)
            err(
                ident.span,
                f"'own {name}': 'own' lists records, and '{name}' is "
                f"{'an' if kind == 'input' else 'a'} {kind} of controller '{controller}': "
                f"{why}; leave it out of 'own'",
            )
            continue
        advice = did_you_mean(name, records) or (
            f"; record it in the table ('record {name} = ...') or leave it out of 'own'"
        )
        err(
            ident.span,
            f"'own {name}': controller '{controller}' records no '{name}' "
            f"(its records: {', '.join(records) or 'none'}){advice}",
        )
