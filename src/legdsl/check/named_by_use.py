"""An unknown name told by what its members ask for: a path's (``route.lateral``) is to be
declared with ``path NAME``, a body's (``trunk.pitch``) or a contact's (``toe.z``) is one the
creature lacks. The members are those read of the name where it is written, and, for a
name given to an action, those the action reads of its parameter (``trunk`` given to
``place_foot_3d(leg, body, ...)``, which reads ``body.yaw``): a number, as a ``param`` of
that name would be, cannot stand there (``NameResolver.unknown_name``)."""

from __future__ import annotations

from legdsl.check.values import did_you_mean
from legdsl.ir import controller as ir
from legdsl.ir.model import Model


def told_by_members(
    model: Model,
    name: str,
    dotted: set[str],
    passed: tuple[str, set[str]] | None,
    read: str,
    paths: list[str],
) -> str | None:
    """The message for unknown ``name`` read with ``dotted`` members here, and given to the
    action ``passed[0]``, which reads ``passed[1]`` of it (``paths``: the controller's);
    None when they say nothing."""
    members = dotted | (passed[1] if passed else set())
    if not members:
        return None
    if members <= set(ir.PATH_MEMBERS) and members - set(ir.BODY_MEMBERS):
        own = set(members) - set(ir.BODY_MEMBERS)
        if passed and not dotted and own <= passed[1]:  # only the action reads it as a path
            if near := did_you_mean(name, paths):
                return f"unknown name '{name}'{near}"  # 'trak' for 'track': the path meant
            return (
                f"unknown name '{name}': action '{passed[0]}' takes a path there (it reads "
                f"its {sorted(own)[0]}); declare one with 'path {name}'"
            )
        member = read if read in own else sorted(own)[0]
        return f"unknown name '{name}': '{name}.{member}' reads a path, declared with 'path {name}'"
    bodies = [b.name for b in model.bodies]
    contacts = [c.name for c in model.contacts]
    if members <= set(ir.BODY_MEMBERS) and members <= set(ir.CONTACT_MEMBERS):
        return (  # x, y, z and velocities: a body's or a contact's
            f"creature '{model.name}' has no body or contact '{name}' (its bodies: "
            f"{', '.join(bodies)}; contacts: {', '.join(contacts) or 'none'})"
            f"{did_you_mean(name, [*bodies, *contacts])}"
        )
    if members <= set(ir.BODY_MEMBERS):
        return (
            f"creature '{model.name}' has no body '{name}' (its bodies: "
            f"{', '.join(bodies)}){did_you_mean(name, bodies)}"
        )
    if members <= set(ir.CONTACT_MEMBERS):
        return (
            f"creature '{model.name}' has no contact '{name}' (its contacts: "
            f"{', '.join(contacts) or 'none'}){did_you_mean(name, contacts)}"
        )
    return None
