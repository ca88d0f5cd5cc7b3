"""Notes on a checked creature that are no errors but that a user would not guess.

A leg has one foot contact. Another contact on the same body as the foot (a heel beside
the toe of a flat foot) touches the ground and carries load, but the leg's events
(`touchdown`, `liftoff`), its stances in the metrics and its row of the footfall diagram
are its foot's alone: a heel strike before the toe lands is no touchdown of the leg.
"""

from __future__ import annotations

from legdsl.ir.model import Model


def leg_contact_notes(model: Model) -> list[str]:
    """One note per leg whose foot's body carries other contacts."""
    body_of = {c.name: c.body for c in model.contacts}
    notes = []
    for leg in model.legs:
        body = body_of.get(leg.foot)
        others = [c.name for c in model.contacts if c.body == body and c.name != leg.foot]
        if body is None or not others:
            continue
        named = ", ".join(f"'{n}'" for n in others)
        notes.append(
            f"{model.name}: leg '{leg.name}' has its foot '{leg.foot}' on '{body}' beside "
            f"the contact(s) {named}, which are not its foot: touchdown({leg.name}), "
            f"liftoff({leg.name}), the leg's stances in legdsl metrics and its footfall row "
            f"see '{leg.foot}' alone (the others get footfall rows of their own)"
        )
    return notes
