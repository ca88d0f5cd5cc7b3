"""A creature whose numbers, each within a double, combine past one in its dynamics; a start
whose position or angle is past what a run can mean.

A mass times a length squared over 1.8e308 (a link 1e200 m long) makes the lowered dynamics
hold ``inf``, which the printed code cannot name; lowering finds that only after seconds of
sympy (lower/symbolic.py refuses it there too). This bound, from the numbers alone, refuses it
at checking, so that a file ``legdsl check`` accepts also compiles: every constant of the
dynamics is a sum of a few products of a mass (or an inertia) with at most two lengths, or with
gravity and one length, each at most the creature's whole mass times its reach from the root.

``initial_past_reason`` judges each 'initial' position and angle alike: a position whose
potential energy ``m g z`` (by the same bound) passes a double, or that is more than ``FAR``
times the creature's reach from the origin (a double there keeps it only to a millionth of
the creature, coarser than a step's motion), and an angle of more than ``TURNS`` turns (the
angle it points at is then the rounding's, not the writer's) are refused where written.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from legdsl.ir.model import Body, Joint
from legdsl.lang.errors import Span

MARGIN = 64.0  # the few terms a constant sums, with room to spare
FAR = 1e9  # reaches of the creature: an initial position this far from the origin
TURNS = 1000  # an initial angle of more turns than this


def overflow_message(creature: str) -> str:
    return (
        f"creature '{creature}' gives its dynamics numbers past a double (1.8e308), such as "
        "a mass times a length squared; write it on a smaller scale (lengths and masses "
        "nearer 1 m and 1 kg: 'legdsl scale FILE --by L' rescales it whole)"
    )


def past_a_double(bodies: Sequence[Body], joints: Sequence[Joint], gravity: float) -> Span | None:
    """The body to blame where the dynamics' constants may pass a double (the one farthest
    from the root, by the lengths leading to it), or None."""
    reach = reaches(bodies, joints)
    mass = sum(b.mass for b in bodies)
    inertia = sum(abs(x) for b in bodies for row in b.inertia for x in row)
    most = max(reach.values(), default=0.0)
    bounds = (mass * most * most, mass * gravity * most, mass * gravity, inertia)
    if all(math.isfinite(MARGIN * x) for x in bounds):
        return None
    for body in bodies:  # one whose own numbers pass it, else the farthest from the root
        own = (body.mass * (reach[body.name] + 1.0) * (reach[body.name] + 1.0) * (gravity + 1.0), *body.inertia[0],
               *body.inertia[1], *body.inertia[2])  # fmt: skip
        if not all(math.isfinite(MARGIN * x) for x in own):
            return body.span
    return max(bodies, key=lambda b: reach[b.name]).span


def reaches(bodies: Sequence[Body], joints: Sequence[Joint]) -> dict[str, float]:
    """Each body's reach from the root (m): the lengths leading to it, its com and length."""
    above = {j.child: j for j in joints}
    reach: dict[str, float] = {}
    for body in bodies:  # tree order: a parent's reach is known before its children's
        joint = above.get(body.name)
        base = reach.get(body.parent, 0.0) if body.parent else 0.0
        offset = math.hypot(*joint.origin) if joint is not None and body.parent else 0.0
        reach[body.name] = base + offset + math.hypot(*body.com) + (body.length or 0.0)
    return reach


def initial_past_reason(
    bodies: Sequence[Body],
    joints: Sequence[Joint],
    gravity: float,
    given: Sequence[tuple[str, str, float, Span]],
) -> list[tuple[Span, str]]:
    """The 'initial' values ``given`` (each coordinate's name, kind 'length' or 'angle', value
    in m or rad, and span) past what a run can mean, each with its error (see the module
    docstring)."""
    size = max(reaches(bodies, joints).values(), default=0.0) or 1.0
    mass = sum(b.mass for b in bodies)
    found = []
    for name, kind, value, span in given:
        if kind == "length":
            energy = MARGIN * mass * max(gravity, 1.0) * abs(value)
            if math.isfinite(energy) and abs(value) <= FAR * size:
                continue
            why = (
                "its potential energy (m g z) is past a double (1.8e308)"
                if not math.isfinite(energy)
                else f"a double keeps a position there to {abs(value) * 2.2e-16:.2g} m only, "
                "coarser than the creature's motion in a step"
            )
            ratio = abs(value) / size
            far = f"{ratio:.3g} times" if math.isfinite(ratio) else "more than 1.8e308 times"
            found.append((span, (
                f"the initial {name}, {value:g} m, is {far} the creature's reach "
                f"({size:.3g} m) from the origin: {why}; start it within "
                f"{FAR * size:.3g} m of the origin"
            )))  # fmt: skip
        elif kind == "angle" and not abs(value) <= TURNS * math.tau:
            turned = math.degrees(math.remainder(value, math.tau)) if math.isfinite(value) else 0
            rounded = abs(value) * 2.2e-16 > 1e-6  # a double keeps it to over a microradian
            how = (
                f"where it points is the rounding's, not what was written (as a double it "
                f"reduces to {turned:.4g} deg)"
                if rounded
                else f"it reduces to {turned:.4g} deg"
            )
            found.append((span, (
                f"the initial {name}, {math.degrees(value):g} deg, is "
                f"{abs(value) / math.tau:.3g} turns: {how}; write the angle meant, within a "
                f"turn (such as '{name} = {turned:.4g} deg'{' if that is it' if rounded else ''})"
            )))  # fmt: skip
    return found
