"""A creature whose numbers, each within a double, combine past one in its dynamics.

A mass times a length squared over 1.8e308 (a link 1e200 m long) makes the lowered dynamics
hold ``inf``, which the printed code cannot name; lowering finds that only after seconds of
sympy (lower/symbolic.py refuses it there too). This bound, from the numbers alone, refuses it
at checking, so that a file ``legdsl check`` accepts also compiles: every constant of the
dynamics is a sum of a few products of a mass (or an inertia) with at most two lengths, or with
gravity and one length, each at most the creature's whole mass times its reach from the root.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from legdsl.ir.model import Body, Joint
from legdsl.lang.errors import Span

MARGIN = 64.0  # the few terms a constant sums, with room to spare


def overflow_message(creature: str) -> str:
    return (
        f"creature '{creature}' gives its dynamics numbers past a double (1.8e308), such as "
        "a mass times a length squared; write it on a smaller scale (lengths and masses "
        "nearer 1 m and 1 kg: 'legdsl scale FILE --by L' rescales it whole)"
    )


def past_a_double(bodies: Sequence[Body], joints: Sequence[Joint], gravity: float) -> Span | None:
    """The body to blame where the dynamics' constants may pass a double (the one farthest
    from the root, by the lengths leading to it), or None."""
    above = {j.child: j for j in joints}
    reach: dict[str, float] = {}
    for body in bodies:  # tree order: a parent's reach is known before its children's
        joint = above.get(body.name)
        base = reach.get(body.parent, 0.0) if body.parent else 0.0
        offset = math.hypot(*joint.origin) if joint is not None and body.parent else 0.0
        reach[body.name] = base + offset + math.hypot(*body.com) + (body.length or 0.0)
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
