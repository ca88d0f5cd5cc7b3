"""The legs a controller's ``roles`` bind, and the error for a leg its creature lacks.

A leg the creature does not declare is told with the legs it does. A ``roles`` line the
controller takes from another (``extends``, ``include``) names the legs of the creature that
line was written for: a creature with other leg names (``lf, rf, lh, rh`` for ``fl, fr, rl,
rr``) got one error per leg per controller, naming neither its legs nor the fix, which is a
``roles`` line of its own in the controller (it replaces the one taken).
"""

from __future__ import annotations

from collections.abc import Callable, Collection

from legdsl.check.values import did_you_mean
from legdsl.lang import ast
from legdsl.lang.errors import Span

_BOUND = "roles are bound to legs declared with 'leg NAME { ... }'"


def _shape(item: ast.RolesDecl) -> str:
    """The ``roles`` line with a placeholder for each leg: 'roles active = (LEG, LEG), ...'."""
    roles = (
        f"{r.name.name} = "
        + (f"({', '.join('LEG' for _ in r.legs)})" if len(r.legs) > 1 else "LEG")
        for r in item.roles
    )
    return "roles " + ", ".join(roles)


def role_legs(
    item: ast.RolesDecl,
    creature: str,
    legs: Collection[str],
    controller: ast.ControllerDecl,
    broken: Collection[str],
    err: Callable[[Span, str], None],
) -> dict[str, tuple[str, ...]]:
    """Each role's legs among ``legs`` (the creature's), the unknown ones told: each at its
    place in a ``roles`` line of the controller's own, once for a line it takes from
    another (at its first unknown leg, with the line to write in ``controller``)."""
    has = f"creature '{creature}' has {', '.join(legs) or 'no legs'}"
    unknown = [leg for role in item.roles for leg in role.legs
               if leg.name not in legs and leg.name not in broken]  # fmt: skip
    taken = bool(unknown) and bool(unknown[0].span.within)  # from a base or a shared part
    if taken:
        names = ", ".join(f"'{n}'" for n in dict.fromkeys(leg.name for leg in unknown))
        err(
            unknown[0].span,
            f"unknown leg{'s' if len(unknown) > 1 else ''} {names}; {_BOUND} ({has}), and this "
            f"'roles' line is taken from another controller's: give controller "
            f"'{controller.name.name}' ({controller.name.span}) a line of its own with its legs, "
            f"'{_shape(item)}' (it replaces the line taken)",
        )
    else:
        for leg in unknown:
            err(
                leg.span,
                f"unknown leg '{leg.name}'; {_BOUND} ({has}){did_you_mean(leg.name, legs)}",
            )
    return {
        role.name.name: tuple(x.name for x in role.legs if x.name in legs and x.name not in broken)
        for role in item.roles
    }
