"""Actuators on joint coordinates (spring, servo, force or torque) and contact points on
bodies."""

from __future__ import annotations

from collections.abc import Collection

from legdsl.check.scope import CreaturePart
from legdsl.check.values import article, did_you_mean, unit_hint
from legdsl.ir.model import NON_NEGATIVE, Actuator, Body, Contact, Dof, setting_kind
from legdsl.lang import ast
from legdsl.lang.units import KINDS

ACTUATOR_ARGS = {
    "spring": ("k", "b", "rest", "max"),
    "servo": ("kp", "kv", "setpoint", "max"),
    "force": ("max",),
}


class ActuatorChecker(CreaturePart):
    """Checks actuator and contact declarations."""

    def _not_a_coordinate_hint(
        self, coord: str, dofs: dict[str, Dof], welded: Collection[str] = ()
    ) -> str:
        """How to name the coordinate meant: a gimbal's or ball's own, none for the root's or
        a fixed joint's (``welded``: the names of the fixed joints)."""
        own = [d.name for d in dofs.values() if d.joint == coord]
        if len(own) > 1:
            return f"; joint '{coord}' has the coordinates {', '.join(own)}: put it on one of them"
        if coord in welded:
            shown = ", ".join(list(dofs)[:8]) + (", ..." if len(dofs) > 8 else "")
            return (
                f"; joint '{coord}' is fixed, which has no coordinate to drive: make it a "
                f"revolute or prismatic joint, or put the actuator on another joint's "
                f"coordinate ({shown or 'the creature has none'})"
            )
        root = {"x", "z", "pitch"} if self.planar else {"x", "y", "z", "roll", "pitch", "yaw"}
        if coord in root:
            return (
                f"; '{coord}' is the free root's, which no actuator drives: put it on a joint "
                "and let the legs push the body"
            )
        shown = ", ".join(list(dofs)[:8]) + (", ..." if len(dofs) > 8 else "")
        return did_you_mean(coord, dofs) or (
            f"; put it on one of the joints' coordinates ({shown})"
            if dofs
            else "; the creature has no joint to drive: hang a body from another by a joint"
        )

    def actuator(
        self, decl: ast.ActuatorDecl, dofs: dict[str, Dof], welded: Collection[str] = ()
    ) -> Actuator | None:
        """The actuator ``decl`` on one of ``dofs``; ``welded``: the fixed joints' names."""
        # a second of one name is checked, but the first is the one the rest sees
        declared = self.declare(decl.name, "actuator")
        kind = decl.kind.name
        if kind == "torque":
            kind = "force"
        if kind not in ACTUATOR_ARGS:
            self.err(
                decl.kind.span,
                f"unknown actuator kind '{kind}'; use spring (eq. 1), servo (eq. 5), force or torque"
                + did_you_mean(kind, [*ACTUATOR_ARGS, "torque"]),
            )
            return None
        dof = dofs.get(decl.coordinate.name)
        coord = decl.coordinate.name
        if dof is None and any(coord == j or coord.startswith(j + "_") for j in self.unsettled):
            return None  # on a joint whose kind is wrong, which is reported there
        if dof is None:
            self.err(
                decl.coordinate.span,
                f"actuator '{decl.name.name}' is on '{decl.coordinate.name}', which is not a "
                f"joint coordinate{self._not_a_coordinate_hint(coord, dofs, welded)}",
            )
            return None
        rotary = dof.motion == "hinge"
        kinds = {
            key: setting_kind(key, rotary)
            for key in ("k", "b", "kp", "kv", "rest", "setpoint", "max")
        }
        joint_desc = f"{'revolute' if rotary else 'sliding'} coordinate '{dof.name}'"
        params: dict[str, float] = {}
        given: set[str] = set()  # written, even if wrong (then reported on its own)
        limit = None
        for arg in decl.args:
            if arg.keyword is None:
                self.err(
                    arg.span,
                    f"name each argument, as in {kind}({', '.join(a + ' = ...' for a in ACTUATOR_ARGS[kind])})",
                )
                continue
            key = arg.keyword.name
            if key not in ACTUATOR_ARGS[kind]:
                self.err(
                    arg.keyword.span,
                    f"a {kind} has no '{key}'; it takes {', '.join(ACTUATOR_ARGS[kind])}{did_you_mean(key, ACTUATOR_ARGS[kind])}",
                )
                continue
            if key in given:
                self.err(arg.keyword.span, f"'{key}' is given twice")
                continue
            given.add(key)
            want = kinds[key]
            wrong = self.wrong_motion(arg.value, want)
            if wrong:
                written = decl.kind.name  # 'torque' or 'force' as the file says it
                other = "sliding" if rotary else "revolute"
                self.err(
                    arg.value.span,
                    f"'{key}' of a {written} on the {joint_desc} must be {article(want)} {want} "
                    f"({unit_hint(want)}); this is {article(wrong)} {wrong}, which belongs on a "
                    f"{other} joint: give it in {unit_hint(want)}, or put the actuator on a "
                    f"{other} joint's coordinate",
                )
                continue
            v = self.scalar(arg.value, want, f"'{key}'")
            if v is None:
                continue
            if key in NON_NEGATIVE and v < 0:
                self.err(arg.value.span, f"'{key}' must not be negative")
                continue
            if key == "max":
                limit = v
            else:
                params[key] = v
        required = {"spring": ("k",), "servo": ("kp",), "force": ()}[kind]
        for key in required:
            if key not in given:
                self.err(
                    decl.kind.span,
                    f"a {kind} needs '{key}', e.g. {kind}({key} = ... {unit_hint(kinds[key])})",
                )
        defaults = {
            "spring": {"b": 0.0, "rest": dof.initial},
            "servo": {"kv": 0.0, "setpoint": dof.initial},
            "force": {"value": 0.0},
        }[kind]
        for key, v in defaults.items():
            params.setdefault(key, v)
        order = {
            "spring": ("k", "b", "rest"),
            "servo": ("kp", "kv", "setpoint"),
            "force": ("value",),
        }[kind]
        if not declared:
            return None
        return Actuator(
            decl.name.name,
            kind,
            dof.name,
            tuple((k, params.get(k, 0.0)) for k in order),
            limit,
            rotary,
            decl.span,
        )

    def wrong_motion(self, value: ast.Value, want: str) -> str | None:
        """The linear/angular twin of ``want`` if ``value`` has that dimension instead."""
        twins = {
            "angular stiffness": "linear stiffness", "linear stiffness": "angular stiffness",
            "angular damping": "linear damping", "linear damping": "angular damping",
            "angle": "length", "length": "angle", "torque": "force", "force": "torque",
        }  # fmt: skip
        node = value
        while isinstance(node, ast.Neg):
            node = node.value
        if (
            isinstance(node, ast.Number)
            and want in twins
            and node.quantity.dim == KINDS[twins[want]][0]
        ):
            return twins[want]
        return None

    def contact(self, decl: ast.ContactDecl, bodies: dict[str, Body]) -> Contact | None:
        declared = self.declare(decl.name, "contact")  # else the first is the one seen
        body = bodies.get(decl.body.name)
        if body is None:
            names = list(bodies)
            shown = ", ".join(names[:8]) + (", ..." if len(names) > 8 else "")
            advice = did_you_mean(decl.body.name, bodies) or (
                f"; put it on one of this creature's bodies ({shown})"
                if names
                else "; declare the body first"
            )
            self.err(
                decl.body.span,
                f"contact '{decl.name.name}' is on an unknown body '{decl.body.name}'{advice}",
            )
            return None
        point = (
            self.location(decl.at, body, contact=True) if decl.at is not None else (0.0, 0.0, 0.0)
        )
        return Contact(decl.name.name, body.name, point, decl.span) if declared else None
