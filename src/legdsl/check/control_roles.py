"""Roles and their bindings: which legs each role can stand for once the table's swaps have
run, and the aliases read through a role checked on every one of those legs."""

from __future__ import annotations

from legdsl.check.control_names import AliasUse, Scope
from legdsl.check.control_stmts import Elaborator
from legdsl.check.control_words import no_alias_message
from legdsl.ir import controller as ir
from legdsl.ir.model import Model
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostics


def reachable_bindings(
    roles: dict[str, tuple[str, ...]], states: tuple[ir.State, ...]
) -> tuple[tuple[ir.Binding, ...], dict[tuple[int, int], int]]:
    """Every role binding reachable through the table's swaps, the initial one first, and the
    binding each (binding while waiting, state) leads to once the state's swaps are done."""
    found: list[ir.Binding] = [tuple(sorted(roles.items()))]
    after: dict[tuple[int, int], int] = {}
    i = 0
    while i < len(found):
        for s, state in enumerate(states):
            binding = dict(found[i])
            for swap in swaps(state.body):
                binding[swap.first], binding[swap.second] = (
                    binding[swap.second],
                    binding[swap.first],
                )
            key = tuple(sorted(binding.items()))
            if key not in found:
                found.append(key)
            after[(i, s)] = found.index(key)
        i += 1
    return tuple(found), after


def swaps(body: tuple[ir.Stmt, ...]) -> list[ir.Swap]:
    """The swaps of a state, in order, inlined actions included."""
    out: list[ir.Swap] = []
    for s in body:
        if isinstance(s, ir.Swap):
            out.append(s)
        elif isinstance(s, ir.Do):
            out += swaps(s.body)
    return out


def _alike(model: Model, a: str, b: str) -> bool:
    """Two parts that one role's alias may name on different legs: same kind and units."""

    def signature(name: str) -> tuple[str, ...]:
        for act in model.actuators:
            if act.name == name:
                return ("actuator", act.kind, str(act.rotary))
        for dof in model.dofs:
            if dof.name == name:
                return ("coord", dof.motion)
        if any(c.name == name for c in model.contacts):
            return ("contact",)
        return ("body", str(model.body(name).length is not None))

    return signature(a) == signature(b)


def check_aliases(
    scope: Scope,
    diag: Diagnostics,
    actions: dict[str, ast.ActionDef],
    bindings: tuple[ir.Binding, ...],
    uses: list[AliasUse],
) -> None:
    """Every leg a role is ever bound to has the aliases read through the role, alike."""
    for use in uses:
        role = use.alias.legs.root().role  # a member of a role: every leg of the role
        first = scope.roles.get(role or "", ())
        if not first:
            continue
        expected = scope.aliases[first[0]][use.alias.alias]
        el = Elaborator(scope, diag)
        el.calls = [(call, actions[call.action.name]) for call in use.context]
        reported: set[str] = set()
        for binding in bindings:
            for leg in dict(binding).get(role or "", ()):
                if leg in reported:
                    continue
                aliases = scope.aliases[leg]
                if use.alias.alias not in aliases:
                    el.err(
                        use.span,
                        no_alias_message(leg, role, use.alias.alias, aliases, scope.model.planar),
                    )
                    reported.add(leg)
                elif not _alike(scope.model, aliases[use.alias.alias], expected):
                    el.err(
                        use.span,
                        f"'{use.alias.alias}' names '{aliases[use.alias.alias]}' on leg '{leg}' "
                        f"but '{expected}' on leg '{first[0]}', which differ in kind; a role's "
                        "legs need aliases of one kind",
                    )
                    reported.add(leg)
