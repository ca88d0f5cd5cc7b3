"""How a controller's messages word what they speak of: a value's type, an expression, a
leg's missing member, and the standard library's 3D names a planar creature lacks.

Shared by the controller checker's layers (``control_names``, ``control_exprs``,
``control_stmts``, ``control_args``, ``control_roles``); it knows words, not scopes.
"""

from __future__ import annotations

from legdsl.check.values import did_you_mean
from legdsl.ir import controller as ir
from legdsl.ir.controller import BOOL, ONE, Type
from legdsl.lang import ast
from legdsl.lang.units import describe

# The standard library's aliases for a 3D hip's roll and yaw: a planar leg lacks them
# because the action is 3D, not because the leg forgot an alias.
SPATIAL_ALIASES = frozenset({"roll_servo", "roll_motor", "roll_angle", "yaw_servo", "yaw_angle"})

# The standard library's 3D actions that have a planar counterpart (appended to raibert.leg),
# named when a planar creature calls the 3D one.
PLANAR_COUNTERPARTS = {
    "trim_step_speed": "trim_step_speed_planar",
    "trim_step_speed_from": "trim_step_speed_planar_from",
    "stride_speed": "stride_speed_planar",
    "place_feet_turning": "place_feet_planar",
    "servo_posture_virtual": "servo_pitch_shared",
    "servo_pitch_rate_virtual": "servo_pitch_rate_shared",
}


def describe_type(t: Type) -> str:
    if t == BOOL:
        return "a condition"
    if t is None:
        return "a number of any unit"
    assert isinstance(t, tuple)
    if t == ONE:
        return "a plain number (no unit)"
    word = describe(t)
    if "(" not in word:
        return f"a quantity in {word}"
    return f"{'an' if word[0] in 'aeiou' else 'a'} {word}"


def no_alias_message(
    leg: str, role: str | None, name: str, aliases: dict[str, str], planar: bool = False
) -> str:
    what = f"leg '{leg}'" + (f" (in role '{role}')" if role else "")
    # a planar leg has no sideways members: listing them would offer what is refused
    members = [m for m in ir.LEG_MEMBERS if not (planar and m in ir.SPATIAL_MEMBERS)]
    return (
        f"{what} has no member '{name}'; a leg has {', '.join(members)} and its aliases"
        f"{did_you_mean(name, [*members, *aliases])}"
    )


def expression_text(e: ast.Expr) -> str:
    if isinstance(e, ast.EName):
        return e.ident.name
    if isinstance(e, ast.EAttr):
        return f"{expression_text(e.base)}.{e.attr.name}"
    return "this"
