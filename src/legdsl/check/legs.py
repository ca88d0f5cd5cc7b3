"""Legs: a leg names its joints from the hip outwards, its foot contact and aliases for
the things a controller reaches through it."""

from __future__ import annotations

from legdsl.check.scope import CreaturePart, Scope
from legdsl.check.values import did_you_mean
from legdsl.ir.controller import LEG_CONSTANTS, LEG_MEMBERS
from legdsl.ir.model import Actuator, Body, Contact, Joint, Leg
from legdsl.lang import ast
from legdsl.lang.errors import Span

LEG_PROPS = ("joints", "foot", "alias")


class LegChecker(CreaturePart):
    """Checks leg declarations against the tree, contacts and actuators checked before them."""

    def __init__(self, scope: Scope):
        super().__init__(scope)
        self._sole_of: dict[str, str] = {}  # each contact a leg stands on, and that leg

    def leg(
        self,
        decl: ast.LegDecl,
        joints: list[Joint],
        contacts: list[Contact],
        actuators: list[Actuator],
        bodies: list[Body],
    ) -> Leg | None:
        self.declare(decl.name, "leg")
        joint_names = {j.name for j in joints if j.parent is not None}
        coord_names = {d.name for j in joints for d in j.dofs}
        contact_by = {c.name: c for c in contacts}
        referable = (
            joint_names
            | coord_names
            | {a.name for a in actuators}
            | set(contact_by)
            | {b.name for b in bodies}
        )
        leg_joints: list[str] = []
        listed_at: list[ast.Ident] = []  # each joint listed, where it is written
        foot = None
        soles: list[str] = []
        aliases: list[tuple[str, str]] = []
        alias_at: dict[str, ast.Ident] = {}  # each alias's target, where it is written
        seen: set[str] = set()
        joints_at: Span | None = None  # None too if a joint listed is unknown: told there
        for p in decl.props:
            key = p.key.name
            if key not in LEG_PROPS:
                self.err(
                    p.key.span,
                    f"unknown leg property '{key}'"
                    + (did_you_mean(key, LEG_PROPS) or f"; a leg takes {', '.join(LEG_PROPS)}"),
                )
                continue
            if key in seen and key != "alias":
                self.err(p.key.span, f"'{key}' is given twice for leg '{decl.name.name}'")
                continue
            seen.add(key)
            if key == "joints":
                joints_at = p.value.span
                values = (
                    p.value.values
                    if isinstance(p.value, ast.Many)
                    else (p.value.value,)
                    if isinstance(p.value, ast.One)
                    else ()
                )
                for v in values:
                    ident = self.name_of(v, "a leg joint")
                    if ident is None:
                        joints_at = None
                        continue
                    if ident.name not in joint_names:
                        self.err(
                            ident.span,
                            f"unknown joint '{ident.name}'{did_you_mean(ident.name, joint_names)}",
                        )
                        joints_at = None
                    else:
                        leg_joints.append(ident.name)
                        listed_at.append(ident)
            elif key == "foot":
                soles = self._soles(decl.name.name, p.value, contact_by)
                foot = soles[0] if soles else None
            else:
                if not isinstance(p.value, ast.Assigns):
                    self.err(
                        p.value.span,
                        "write aliases as 'alias spring = leg_l_spring, hip = hip_l_servo'",
                    )
                    continue
                for item in p.value.items:
                    target = self.name_of(item.value, "an alias target")
                    if target is None:
                        continue
                    if target.name not in referable and (
                        target.name in self.names or target.name in self.refused
                    ):
                        continue  # declared, with its mistake told there (an unknown joint)
                    if target.name not in referable:
                        self.err(
                            target.span,
                            f"unknown name '{target.name}'; an alias names an actuator, joint, coordinate, contact or body{did_you_mean(target.name, referable)}",
                        )
                        continue
                    alias = item.target.name
                    if alias in LEG_MEMBERS or alias in LEG_CONSTANTS:
                        self.err(  # a controller's 'main.length' reads the leg's own
                            item.target.span,
                            f"alias '{alias}' would hide the leg's own member '{alias}' (what "
                            f"'{decl.name.name}.{alias}' reads); choose another name",
                        )
                        continue
                    if item.target.name in alias_at:
                        self.err(
                            item.target.span,
                            f"alias '{item.target.name}' is given twice for leg "
                            f"'{decl.name.name}' (first for '{alias_at[item.target.name].name}'); "
                            f"give each alias one target",
                        )
                        continue
                    aliases.append((item.target.name, target.name))
                    alias_at[item.target.name] = target
        if "joints" not in seen:
            self.err(
                decl.name.span, f"leg '{decl.name.name}' needs 'joints' (from the hip outwards)"
            )
        if "foot" not in seen:
            self.err(decl.name.span, f"leg '{decl.name.name}' needs a 'foot' contact")
        if not leg_joints or foot is None:
            return None
        # The foot must hang below the leg's first joint.
        by_child = {j.child: j for j in joints}
        body = contact_by[foot].body
        chain = []
        while body in by_child and by_child[body].parent is not None:
            chain.append(by_child[body].name)
            body = by_child[body].parent or ""
        # A walk that stops short of the root met a misspelt parent, reported in the tree.
        if leg_joints[0] not in chain and body in by_child:
            self.err(
                decl.name.span,
                f"the foot '{foot}' of leg '{decl.name.name}' is not below its first joint "
                f"'{leg_joints[0]}': list the joints from the body down to the foot "
                f"(the joints above '{contact_by[foot].body}': {', '.join(reversed(chain)) or 'none'})",
            )
        if leg_joints[0] in chain:
            # The listed joints are the whole chain of joints that move, hip first, from the
            # highest one listed on it: a weld moves nothing and is left out (a leg with no
            # joint that moves, a peg welded on, names the weld it hangs from).
            top = max(chain.index(j) for j in leg_joints if j in chain)
            # from the foot up to the hip, the highest joint listed, whatever the order they
            # are listed in (told above): 'joints slide, hip' is a leg from 'hip' down
            own = chain[: top + 1]
            moving = {j.name for j in joints if j.kind != "weld"}
            whole = [j for j in chain[top::-1] if j in moving]
            if [j for j in leg_joints if j in moving or j not in chain] != whole and joints_at:
                self.err(
                    joints_at,
                    f"the joints of leg '{decl.name.name}' are not the chain from its hip down "
                    f"to its foot '{foot}', in order: write 'joints {', '.join(whole)}'",
                )
            elif whole and joints_at:
                for ident in listed_at:
                    if ident.name not in moving:
                        self.err(ident.span, _weld_listed(ident.name, decl.name.name, whole))
            self._own_aliases(decl.name.name, own, aliases, alias_at, joints, actuators)
        return Leg(
            decl.name.name, tuple(leg_joints), foot, tuple(aliases), decl.span, tuple(soles[1:])
        )

    def _soles(
        self,
        leg: str,
        value: ast.One | ast.Range | ast.Many | ast.Assigns,
        contact_by: dict[str, Contact],
    ) -> list[str]:
        """``foot sole, heel, toe``: the leg's foot point first, then the other contacts it stands
        on, each declared, listed once, a sole of no other leg and on the first one's body."""
        values = (
            value.values
            if isinstance(value, ast.Many)
            else (value.value,)
            if isinstance(value, ast.One)
            else ()
        )
        if not values:
            self.err(value.span, "a leg names its foot contact: 'foot toe' (or 'foot sole, heel')")
            return []
        soles: list[str] = []
        for v in values:
            ident = self.name_of(v, "a leg's foot")
            if ident is None:
                return []
            name = ident.name
            if name not in contact_by and (
                self.names.get(name, ("",))[0] == "contact" or name in self.refused
            ):
                return []  # declared, with its mistake reported there (on an unknown body, say)
            if name not in contact_by and self.names.get(name, ("",))[0] == "body":
                self.err(ident.span, _body_as_foot(name, contact_by))
                return []
            if name not in contact_by:
                self.err(
                    ident.span,
                    f"unknown contact '{name}'; declare it with 'contact {name} on BODY at tip'{did_you_mean(name, contact_by)}",
                )
                return []
            if name in soles:
                self.err(
                    ident.span,
                    f"contact '{name}' is listed twice in the foot of leg '{leg}'; list it once",
                )
                return []
            other = self._sole_of.get(name)
            if other is not None:
                self.err(
                    ident.span,
                    f"contact '{name}' is already a foot contact of leg '{other}'; a contact is "
                    f"the sole of one leg: declare another contact for leg '{leg}'",
                )
                return []
            first = contact_by[soles[0]] if soles else None
            if first is not None and contact_by[name].body != first.body:
                self.err(
                    ident.span,
                    f"contact '{name}' is on '{contact_by[name].body}', not on '{first.body}' "
                    f"with the foot '{first.name}': the soles of a leg are on one foot body "
                    f"(declare '{name}' on '{first.body}' or leave it out of the foot)",
                )
                return []
            soles.append(name)
        for name in soles:
            self._sole_of[name] = leg
        return soles

    def _own_aliases(
        self,
        leg: str,
        own: list[str],
        aliases: list[tuple[str, str]],
        alias_at: dict[str, ast.Ident],
        joints: list[Joint],
        actuators: list[Actuator],
    ) -> None:
        """An alias for an actuator, joint or coordinate names one on the leg, between its first
        joint and its foot: a controller reaching another leg's spring or the tail's motor
        through this leg (``active.spring``) would drive the wrong thing without a word."""
        joint_of = {d.name: j.name for j in joints for d in j.dofs}
        joint_of |= {j.name: j.name for j in joints}
        joint_of |= {a.name: joint_of.get(a.dof, "") for a in actuators}
        for name, target in aliases:
            on = joint_of.get(target)
            if on and on not in own:
                self.err(
                    alias_at[name].span,
                    f"alias '{name}' of leg '{leg}' names '{target}', on joint '{on}', which is "
                    f"not on the leg (its joints from the hip to the foot: "
                    f"{', '.join(reversed(own))}); alias it in the leg it belongs to, or reach "
                    f"it by its own name",
                )


def _weld_listed(weld: str, leg: str, whole: list[str]) -> str:
    """A weld listed in a leg's joints that move: it is no joint of the leg."""
    return (
        f"joint '{weld}' is a weld ('fixed'): it moves nothing and has no coordinate, so it is "
        f"not one of the joints of leg '{leg}' (its joints that move, from the hip: "
        f"{', '.join(whole)}); leave it out: write 'joints {', '.join(whole)}'"
    )


def _body_as_foot(body: str, contact_by: dict[str, Contact]) -> str:
    """A body named as a leg's foot: a foot is a contact, a point on its body."""
    on = [c.name for c in contact_by.values() if c.body == body]
    advice = (
        f"write 'foot {on[0]}', the contact on '{body}'"
        if len(on) == 1
        else f"write one of the contacts on '{body}', as in 'foot {on[0]}' (its contacts: "
        f"{', '.join(on)})"
        if on
        else f"declare one, as in 'contact {body}_toe on {body} at tip', and write "
        f"'foot {body}_toe'"
    )
    return f"'{body}' is a body, and a leg's foot names a contact, a point on a body: {advice}"
