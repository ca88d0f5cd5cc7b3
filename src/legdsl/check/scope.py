"""What the parts of one creature's check share.

``Scope`` is the state: the shared diagnostics, whether the creature is planar, and the
names declared so far (a name is unique across a creature's bodies, joints, coordinates,
actuators, contacts and legs). ``CreaturePart`` is the base of each part's checker
(``tree``, ``bodies``, ``joints``, ``actuators``, ``ground``, ``legs``): a ``ValueChecker``
on that scope, with the readers that depend on it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from legdsl.check.values import ValueChecker
from legdsl.ir.controller import BUILTIN_VALUES
from legdsl.ir.model import Body, Vec3
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostics, Span

# The names every controller has, which no part of a creature may take.
CONTROLLER_BUILTINS = {
    "com": "the creature's centre of mass",
    "terrain": "the terrain ahead",
    **{name: "a built-in value" for name in BUILTIN_VALUES},
}


@dataclass(frozen=True)
class Scope:
    """One creature's check: where errors go, planar or spatial, and the names taken so far."""

    diag: Diagnostics
    planar: bool
    names: dict[str, tuple[str, Span]]  # name -> (what it names, where it was declared)
    # Joints whose kind was wrong and could not be guessed, or of a body declared twice: their
    # coordinates are unknown, so a name on them is not reported again as unknown.
    unsettled: set[str] = field(default_factory=set)
    # Names a declaration was refused (taken already): what uses them is not told again.
    refused: set[str] = field(default_factory=set)


class CreaturePart(ValueChecker):
    """A part of a creature's check; every part built on one ``Scope`` shares its state."""

    def __init__(self, scope: Scope):
        super().__init__(scope.diag)
        self.planar = scope.planar
        self.names = scope.names
        self.unsettled = scope.unsettled
        self.refused = scope.refused

    def point(
        self, value: ast.Value, what: str, kind: str = "length", example: str | None = None
    ) -> Vec3 | None:
        """A point or direction: (x, z) in a planar creature, (x, y, z) otherwise."""
        if self.planar:
            v = self.vector(value, kind, 2, what, example=example)
        else:
            v = self.vector(value, kind, 3, what, "x, y, z", example, " in a spatial creature")
        if v is None:
            return None
        return (v[0], 0.0, v[1]) if self.planar else (v[0], v[1], v[2])

    def unit_vector(self, value: ast.Value, what: str) -> Vec3 | None:
        v = self.point(value, what, "dimensionless", self._direction_example(value))
        if v is None:
            return None
        # a direction: scaled by its largest component first, so that (1e-300, 0, 0) is x,
        # as (1e200, 1e200, 0) is the diagonal; only (0, 0, 0) has none
        largest = max(abs(c) for c in v)
        if largest == 0.0:
            down = "(0, -1)" if self.planar else "(0, 0, -1)"
            self.err(value.span, f"{what} has zero length; give a direction such as {down}")
            return None
        scaled = (v[0] / largest, v[1] / largest, v[2] / largest)
        norm = math.hypot(*scaled)  # between 1 and sqrt(3)
        return (scaled[0] / norm, scaled[1] / norm, scaled[2] / norm)

    def _direction_example(self, value: ast.Value) -> str:
        """A direction to show for ``value``: along the axis it names (``axis z``: (0, 0, 1)),
        else along x; never (0, 0, 0), which has no direction."""
        axes = "xz" if self.planar else "xyz"
        name = value.ident.name.lower() if isinstance(value, ast.NameValue) else "x"
        along = axes.index(name) if len(name) == 1 and name in axes else 0
        return "(" + ", ".join("1" if i == along else "0" for i in range(len(axes))) + ")"

    def name_of(self, value: ast.Value, what: str) -> ast.Ident | None:
        if isinstance(value, ast.NameValue):
            return value.ident
        self.err(value.span, f"{what} must be a name")
        return None

    def declare(self, ident: ast.Ident, kind: str) -> bool:
        prior = self.names.get(ident.name)
        builtin = CONTROLLER_BUILTINS.get(ident.name)
        if builtin is not None or prior is not None:
            self.refused.add(ident.name)
        if builtin is not None:
            # a part so named and the controllers' own name would hide one another
            self.err(
                ident.span,
                f"the name '{ident.name}' is taken: every controller reads it as {builtin}; "
                f"give the {kind} another name, as in '{ident.name}_{kind.split()[-1]}'",
            )
            return False
        if prior is not None:
            self.err(
                ident.span,
                f"the name '{ident.name}' is already used by the {prior[0]} at {prior[1]}"
                # the prior's instance, unless it is this one (the error names it once)
                f"{prior[1].within if prior[1].within != ident.span.within else ''}; "
                "names in a creature must be unique",
            )
            return False
        self.names[ident.name] = (kind, ident.span)
        return True

    def location(self, value: ast.Value, parent: Body | None, contact: bool = False) -> Vec3:
        """A joint's location in its parent's frame, or a contact's point in its body's frame."""
        what, whose = ("contact point", "body") if contact else ("joint location", "parent body")
        if isinstance(value, ast.NameValue):
            if value.ident.name != "tip":
                self.err(
                    value.span,
                    f"a {what} is a point such as (0.1 m, 0 m) or 'tip' (the {whose}'s link end)",
                )
                return (0.0, 0.0, 0.0)
            if parent is None:
                return (0.0, 0.0, 0.0)
            if parent.length is None and f"{parent.name}.length" not in self.diag.unknown:
                self.err(value.span, f"'at tip' needs a length on the {whose} '{parent.name}'")
            return parent.tip
        return self.point(value, f"the {what}") or (0.0, 0.0, 0.0)
