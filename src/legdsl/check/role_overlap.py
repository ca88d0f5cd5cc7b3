"""Each leg in one role: a leg bound to two roles (or twice to one) would take the commands
of both, which conflict, and a swap would leave it in both."""

from __future__ import annotations

from collections.abc import Callable, Iterable

from legdsl.lang import ast
from legdsl.lang.errors import Span


def check_one_role_per_leg(
    decl: ast.RolesDecl, legs_declared: Iterable[str], err: Callable[[Span, str], None]
) -> None:
    """Told at the second mention of a leg. Two roles bound to exactly the same legs are one
    virtual leg under two names (a one-leg hopper's `active = main, spare = (main)`, whose
    swap changes nothing), not a conflict between virtual legs, unless a leg is in no role:
    `a = f, b = f` beside a leg `r` is a slip for `b = r`."""
    in_roles = {leg.name for role in decl.roles for leg in role.legs}
    unbound = [leg for leg in legs_declared if leg not in in_roles]
    verb = "is" if len(unbound) == 1 else "are"
    hint = f"; {_listed(unbound)} {verb} in no role" if unbound else ""
    first_role: dict[str, str] = {}
    for role in decl.roles:
        seen: set[str] = set()
        for leg in role.legs:
            name = role.name.name
            if leg.name in seen:
                err(
                    leg.span,
                    f"leg '{leg.name}' is named twice in role '{name}'; name each leg once{hint}",
                )
                continue
            seen.add(leg.name)
            other = first_role.setdefault(leg.name, name)
            if other != name and (unbound or not _same_legs(decl, other, name)):
                err(
                    leg.span,
                    f"leg '{leg.name}' is in role '{other}' and in role '{name}', so it would "
                    f"take both roles' commands; put each leg in one role{hint}",
                )


def _same_legs(decl: ast.RolesDecl, a: str, b: str) -> bool:
    legs = {role.name.name: {leg.name for leg in role.legs} for role in decl.roles}
    return legs[a] == legs[b]


def _listed(names: list[str]) -> str:
    quoted = [f"'{n}'" for n in names]
    return quoted[0] if len(quoted) == 1 else ", ".join(quoted[:-1]) + " and " + quoted[-1]
