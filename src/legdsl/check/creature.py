"""Check a parsed .leg file's creature and build the model IR.

Every mistake found is collected (not just the first) and raised together as
one ``LegError``, sorted by position. ``CreatureChecker`` reads the creature's
own lines (planar or spatial, gravity), expands its templates' instances
(``templates``; mirrored ones are reflected at the end, ``mirror``) and hands each kind of declaration to
its part, in this order, all on one ``Scope`` (``legdsl.check.scope``):

- ``tree``: the bodies in tree order, each with the joint above it
  (``bodies``: mass, inertia, shape; ``joints``: axes, coordinates, initial state);
- ``actuators``: actuators and contacts;
- ``ground``: the ground block and its terrain;
- ``legs``: legs, which refer to all of the above.

The controller half is checked in ``legdsl.check.controller``.
"""

from __future__ import annotations

from legdsl.check.actuators import ActuatorChecker
from legdsl.check.ground import GroundChecker
from legdsl.check.legs import LegChecker
from legdsl.check.magnitudes import initial_past_reason, overflow_message, past_a_double
from legdsl.check.mirror import mirror_parts
from legdsl.check.scope import Scope
from legdsl.check.simulation import SimulationChecker
from legdsl.check.templates import expand
from legdsl.check.tree import TreeChecker
from legdsl.check.values import MAX_NAME, ValueChecker, did_you_mean, too_long
from legdsl.ir.model import Model, SimulationDefaults
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostics, Span


class CreatureChecker(ValueChecker):
    """Checks one creature declaration; errors go to the shared diagnostics."""

    def __init__(self, decl: ast.CreatureDecl, diag: Diagnostics, source: str):
        super().__init__(diag)
        self.decl = decl
        self.source = source
        self.planar = True
        self.names: dict[str, tuple[str, Span]] = {}

    def unmade(self, model: Model) -> set[str]:
        """The parts declared with a mistake told at them that ``model`` lacks (an actuator on
        an unknown coordinate, what an instance that could not be made would declare): a
        controller naming one is no news."""
        made = {p.name for parts in (model.bodies, model.joints, model.actuators) for p in parts}
        made |= {c.name for c in model.contacts} | {leg.name for leg in model.legs}
        kinds = ("body", "joint", "actuator", "contact", "leg")
        return {n for n, (kind, _) in self.names.items() if kind in kinds and n not in made}

    def check(self) -> Model | None:
        d = self.decl
        if len(d.name.name) > MAX_NAME:
            self.err(d.name.span, too_long("creature", d.name.name))
        flags = [i for i in d.items if isinstance(i, ast.Flag)]
        if not flags:
            self.err(
                d.name.span,
                f"say whether creature '{d.name.name}' is 'planar' or 'spatial' (3D): "
                "add a line 'planar' or 'spatial' to its block",
            )
        else:
            for extra in flags[1:]:
                self.err(extra.span, "'planar' or 'spatial' may be given once")
            self.planar = flags[0].name == "planar"

        gravity = 9.81
        given: ast.Prop | None = None
        for prop in (i for i in d.items if isinstance(i, ast.Prop)):
            if prop.key.name == "gravity" and given is not None:
                self.err(prop.key.span, f"'gravity' is given twice (first at {given.key.span})")
            elif prop.key.name == "gravity":
                given = prop
                g = self.one_scalar(prop, "acceleration", "gravity")
                if g is not None and g < 0:
                    self.err(
                        prop.value.span,
                        "gravity is the magnitude of the acceleration, which points along -z: "
                        f"write it without the sign, as in 'gravity {-g:g} m/s^2'",
                    )
                elif g is not None:
                    gravity = g
            else:
                self.err(
                    prop.key.span,
                    f"unknown creature property '{prop.key.name}'"
                    + (
                        did_you_mean(prop.key.name, ["gravity", "planar", "spatial"])
                        or "; a creature holds 'planar' or 'spatial', 'gravity', bodies, actuators, "
                        "contacts, legs and a ground block"
                    ),
                )

        expansion = expand(d, self.diag, self.planar)
        items = expansion.items
        for what, ident in expansion.unmade:  # declared, with its mistake told at the instance
            self.names.setdefault(ident.name, (what, ident.span))
        scope = Scope(self.diag, self.planar, self.names)
        tree, attached = TreeChecker(scope), ActuatorChecker(scope)
        bodies_decl = [i for i in items if isinstance(i, ast.BodyDecl)]
        order = tree.tree_order(d.name, bodies_decl)
        bodies, joints, q0, v0 = tree.build_tree(order)
        by_body = {b.name: b for b in bodies}
        # The free root's coordinates (a planar creature's x, z, pitch) are no joint's:
        # the legs push the body, so no actuator may drive them.
        dofs = {dof.name: dof for j in joints if j.parent is not None for dof in j.dofs}
        welded = {j.name for j in joints if j.parent is not None and not j.dofs}

        actuators = [
            a
            for i in items
            if isinstance(i, ast.ActuatorDecl)
            for a in [attached.actuator(i, dofs, welded)]
            if a is not None
        ]
        contacts = [
            c
            for i in items
            if isinstance(i, ast.ContactDecl)
            for c in [attached.contact(i, by_body)]
            if c is not None
        ]
        ground = None
        simulation: SimulationDefaults | None = None
        for block in (i for i in items if isinstance(i, ast.BlockDecl)):
            if block.name.name == "simulation":
                if simulation is not None:
                    self.err(block.name.span, "a creature has one simulation block")
                simulation = SimulationChecker(self.diag).simulation(block)
            elif block.name.name != "ground":
                known = ["ground", "simulation"]
                self.err(
                    block.name.span,
                    f"unknown block '{block.name.name}'{did_you_mean(block.name.name, known)}"
                    " (the blocks of a creature are 'ground { ... }' and 'simulation { ... }')",
                )
            elif ground is not None:
                self.err(block.name.span, "a creature has one ground block")
            else:
                ground = GroundChecker(scope).ground(block)
        leg_checker = LegChecker(scope)
        legs = [
            leg_checker.leg(i, joints, contacts, actuators, bodies)
            for i in items
            if isinstance(i, ast.LegDecl)
        ]
        stops = list(tree.joints.stops)
        mirror_parts(expansion.mirrors, bodies, joints, contacts, actuators, stops, q0, v0)

        if not bodies:
            return None
        blamed = past_a_double(bodies, joints, gravity)
        if blamed is not None:
            self.err(blamed, overflow_message(d.name.name))
        for span, message in initial_past_reason(bodies, joints, gravity, tree.joints.given):
            self.err(span, message)
        return Model(
            name=d.name.name,
            source=self.source,
            planar=self.planar,
            gravity=(0.0, 0.0, -gravity),
            bodies=tuple(bodies),
            joints=tuple(joints),
            actuators=tuple(actuators),
            contacts=tuple(contacts),
            ground=ground,
            legs=tuple(leg for leg in legs if leg is not None),
            controllers=(),
            q0=tuple(q0),
            v0=tuple(v0),
            span=d.span,
            simulation=simulation or SimulationDefaults(),
            stops=tuple(stops),
        )
