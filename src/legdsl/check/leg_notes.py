"""Notes on a checked creature that are no errors but that a user would not guess.

A leg stands on the contacts its ``foot`` lists (``foot sole, heel, toe``). Another contact
on the same body (a heel beside the toe of a flat foot, left out of the list) touches the
ground and carries load, but the leg's events (`touchdown`, `liftoff`), its stances in the
metrics and its row of the footfall diagram do not see it: a heel strike before the toe
lands is no touchdown of the leg.

Legs that hang from different bodies (a trunk in two halves on a spine) have their hips
listed by ``legdsl show`` in the root body's frame, whose origin is then the root half's,
not the centre of mass the controllers' ``hip_x`` is measured from: a rear hip placed from
the wrong origin looks right there. The note gives each hip from the centre of mass.

A creature with contacts and no ground block is well-formed (the ground is optional), but its
contacts touch nothing: its feet pass through the floor and a run of it falls.
"""

from __future__ import annotations

from legdsl.ir.model import Model


def leg_contact_notes(model: Model) -> list[str]:
    """One note per leg whose foot's body carries contacts the leg does not list, one for
    legs hanging from several bodies, and one for contacts with no ground to touch."""
    return _no_ground(model) + _foot_notes(model) + _hips_on_several_bodies(model)


def _no_ground(model: Model) -> list[str]:
    """A note when ``model`` has contacts and no ground for them to touch."""
    if model.ground is not None or not model.contacts:
        return []
    names = ", ".join(f"'{c.name}'" for c in model.contacts[:4])
    more = ", ..." if len(model.contacts) > 4 else ""
    return [
        f"{model.name}: it has no ground block, so its contacts ({names}{more}) touch "
        "nothing and a run of it falls through the floor; to stand on the ground, add one: "
        "'ground { normal spring(k = ..., b = ...)  tangent spring(k = ..., b = ...) }'"
    ]


def _hips_on_several_bodies(model: Model) -> list[str]:
    """Each hip from the centre of mass, at zero joint angles, when the legs hang from more
    than one body (every body's frame then parallel to the root's)."""
    joints = {j.name: j for j in model.joints}
    hip_of = {leg.name: joints[leg.joints[0]] for leg in model.legs if leg.joints}
    held = {name: hip.parent for name, hip in hip_of.items()}
    total = sum(b.mass for b in model.bodies)
    if model.planar or len(set(held.values())) < 2 or total <= 0:
        return []
    parent = {b.name: (b.parent, joints[b.joint].origin) for b in model.bodies}

    def origin(body: str | None) -> tuple[float, ...]:  # in the root body's frame
        point: tuple[float, ...] = (0.0, 0.0, 0.0)
        while body is not None and parent[body][0] is not None:
            up, at = parent[body]
            point, body = tuple(p + a for p, a in zip(point, at, strict=True)), up
        return point

    mass_centre = [
        sum(b.mass * (origin(b.name)[k] + b.com[k]) for b in model.bodies) / total for k in range(3)
    ]
    hips = []
    for name, hip in hip_of.items():
        x, y, _ = (
            o + h - c for o, h, c in zip(origin(hip.parent), hip.origin, mass_centre, strict=True)
        )
        hips.append(f"{name} on '{hip.parent}' at ({x:.3f}, {y:.3f}) m")
    x, y, z = mass_centre
    return [
        f"{model.name}: its legs hang from {len(set(held.values()))} bodies; at zero joint "
        f"angles its centre of mass is at ({x:.3f}, {y:.3f}, {z:.3f}) m in the root body's "
        f"frame (where legdsl show puts the hips), and the hips from it (x forward, y left, "
        f"as hip_x and hip_y read them): {'; '.join(hips)}"
    ]


def _foot_notes(model: Model) -> list[str]:
    body_of = {c.name: c.body for c in model.contacts}
    notes = []
    for leg in model.legs:
        body = body_of.get(leg.foot)
        others = [c.name for c in model.contacts if c.body == body and c.name not in leg.soles]
        if body is None or not others:
            continue
        named = ", ".join(f"'{n}'" for n in others)
        notes.append(
            f"{model.name}: leg '{leg.name}' stands on {', '.join(repr(s) for s in leg.soles)} "
            f"on '{body}', beside the contact(s) {named} it does not list: touchdown({leg.name}), "
            f"liftoff({leg.name}), its stances in legdsl metrics and its footfall row do not see "
            f"them; to count them as the leg's, list them: 'foot "
            f"{', '.join([*leg.soles, *others])}'"
        )
    return notes
