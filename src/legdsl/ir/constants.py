"""The values of the model's constants that controllers read (``thigh.length``, ``hip.at_x``,
``active.hip_at_x``; the vocabulary is in ``legdsl.ir.controller``)."""

from __future__ import annotations

from legdsl.ir.model import Model

_AXES = {"x": 0, "y": 1, "z": 2}


def body_constant(model: Model, body: str, member: str) -> float | None:
    """A body's ``length`` (None if it has none), ``mass`` or mass centre ``com_x/y/z``."""
    b = model.body(body)
    if member == "length":
        return b.length
    if member == "mass":
        return b.mass
    return b.com[_AXES[member[-1]]]


def coord_constant(model: Model, coord: str, member: str) -> float:
    """``at_x/y/z``: where the coordinate's joint sits, in its parent body's frame."""
    dof = next(d for d in model.dofs if d.name == coord)
    return model.joint(dof.joint).origin[_AXES[member[-1]]]


def leg_constant(model: Model, leg: str, member: str) -> float:
    """``hip_at_x/y/z``: where the leg's first joint sits, in the frame of the body it hangs from."""
    first = next(g for g in model.legs if g.name == leg).joints[0]
    return model.joint(first).origin[_AXES[member[-1]]]
