"""Notes on a checked creature that are no errors but that a user would not guess.

A leg stands on the contacts its ``foot`` lists (``foot sole, heel, toe``). Another contact
on the same body (a heel beside the toe of a flat foot, left out of the list) touches the
ground and carries load, but the leg's events (`touchdown`, `liftoff`), its stances in the
metrics and its row of the footfall diagram do not see it: a heel strike before the toe
lands is no touchdown of the leg.
"""

from __future__ import annotations

from legdsl.ir.model import Model


def leg_contact_notes(model: Model) -> list[str]:
    """One note per leg whose foot's body carries contacts the leg does not list."""
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
