"""Check a parsed .leg file and build the model IR.

Every mistake found is collected (not just the first) and raised together as
one ``LegError``, sorted by position. The controller half is checked in
``legdsl.check.controller``.
"""

from __future__ import annotations

import math

import numpy as np

from legdsl.check.values import (
    ValueChecker,
    article,
    did_you_mean,
    unit_hint,
)
from legdsl.ir.model import (
    Actuator,
    Body,
    Contact,
    Dof,
    Ground,
    Joint,
    Leg,
    Mat3,
    Model,
    Pad,
    Shape,
    SpringDamper,
    Terrain,
    Vec3,
    setting_kind,
)
from legdsl.lang import ast
from legdsl.lang.errors import Diagnostics, Span
from legdsl.lang.units import KINDS

JOINT_KINDS = ("revolute", "prismatic", "gimbal", "ball", "fixed")
BODY_PROPS = (
    "mass", "inertia", "com", "length", "direction", "shape", "color",
    "axis", "axes", "initial", "velocity", "limits",
)  # fmt: skip
SHAPES = {
    "box": ("x", "y", "z"),
    "frustum": ("r0", "r1"),
    "capsule": ("r",),
    "cylinder": ("r",),
    "sphere": ("r",),
}
ACTUATOR_ARGS = {
    "spring": ("k", "b", "rest", "max"),
    "servo": ("kp", "kv", "setpoint", "max"),
    "force": ("max",),
}
GROUND_PROPS = ("normal", "tangent", "torsion", "friction", "terrain")
LEG_PROPS = ("joints", "foot", "alias")


class CreatureChecker(ValueChecker):
    """Checks one creature declaration; errors go to the shared diagnostics."""

    def __init__(self, decl: ast.CreatureDecl, diag: Diagnostics, source: str):
        super().__init__(diag)
        self.decl = decl
        self.source = source
        self.planar = True
        self.names: dict[str, tuple[str, Span]] = {}

    def point(self, value: ast.Value, what: str, kind: str = "length") -> Vec3 | None:
        """A point or direction: (x, z) in a planar creature, (x, y, z) otherwise."""
        v = self.vector(value, kind, 2 if self.planar else 3, what)
        if v is None:
            return None
        return (v[0], 0.0, v[1]) if self.planar else (v[0], v[1], v[2])

    def unit_vector(self, value: ast.Value, what: str) -> Vec3 | None:
        v = self.point(value, what, "dimensionless")
        if v is None:
            return None
        norm = math.sqrt(sum(c * c for c in v))
        if norm < 1e-12:
            self.err(value.span, f"{what} has zero length; give a direction such as (0, 0, -1)")
            return None
        return (v[0] / norm, v[1] / norm, v[2] / norm)

    def name_of(self, value: ast.Value, what: str) -> ast.Ident | None:
        if isinstance(value, ast.NameValue):
            return value.ident
        self.err(value.span, f"{what} must be a name")
        return None

    def declare(self, ident: ast.Ident, kind: str) -> bool:
        prior = self.names.get(ident.name)
        if prior is not None:
            self.err(
                ident.span,
                f"the name '{ident.name}' is already used by the {prior[0]} at {prior[1]}; "
                "names in a creature must be unique",
            )
            return False
        self.names[ident.name] = (kind, ident.span)
        return True

    # ---------------------------------------------------------- creature
    def check(self) -> Model | None:
        d = self.decl
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
        for prop in (i for i in d.items if isinstance(i, ast.Prop)):
            if prop.key.name == "gravity":
                g = self.one_scalar(prop, "acceleration", "gravity")
                if g is not None:
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

        bodies_decl = [i for i in d.items if isinstance(i, ast.BodyDecl)]
        order = self.tree_order(bodies_decl)
        bodies, joints, q0, v0 = self.build_tree(order)
        by_body = {b.name: b for b in bodies}
        dofs = {dof.name: dof for j in joints for dof in j.dofs}
        for j in joints:
            if j.is_free_3d:
                for name in ("x", "y", "z", "qw", "qx", "qy", "qz"):
                    self.names.setdefault(name, ("coordinate", j.span))

        actuators = [
            a
            for i in d.items
            if isinstance(i, ast.ActuatorDecl)
            for a in [self.actuator(i, dofs)]
            if a is not None
        ]
        contacts = [
            c
            for i in d.items
            if isinstance(i, ast.ContactDecl)
            for c in [self.contact(i, by_body)]
            if c is not None
        ]
        ground = None
        for block in (i for i in d.items if isinstance(i, ast.BlockDecl)):
            if block.name.name != "ground":
                self.err(
                    block.name.span,
                    f"unknown block '{block.name.name}'{did_you_mean(block.name.name, ['ground'])}"
                    " (the only block in a creature is 'ground { ... }')",
                )
            elif ground is not None:
                self.err(block.name.span, "a creature has one ground block")
            else:
                ground = self.ground(block)
        legs = [
            self.leg(i, joints, contacts, actuators, bodies)
            for i in d.items
            if isinstance(i, ast.LegDecl)
        ]

        if not bodies:
            return None
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
        )

    def one_scalar(self, prop: ast.Prop, kind: str, what: str) -> float | None:
        if not isinstance(prop.value, ast.One):
            self.err(prop.value.span, f"'{prop.key.name}' takes one value")
            return None
        return self.scalar(prop.value.value, kind, what)

    # ---------------------------------------------------------- the link tree
    def tree_order(self, decls: list[ast.BodyDecl]) -> list[ast.BodyDecl]:
        """Bodies with parents before children; reports duplicates, roots and cycles."""
        by_name: dict[str, ast.BodyDecl] = {}
        for b in decls:
            if b.name.name in by_name:
                first = by_name[b.name.name]
                self.err(
                    b.name.span,
                    f"body '{b.name.name}' is declared twice (a body has one parent); "
                    f"the first is at {first.name.span}",
                )
                continue
            by_name[b.name.name] = b
        roots = [b for b in by_name.values() if not isinstance(b.attach, ast.AttachJoint)]
        if not roots and by_name:
            self.err(
                self.decl.name.span,
                f"creature '{self.decl.name.name}' has no root body: "
                "make one body 'free' (it flies) or 'fixed' (welded to the world)",
            )
        elif not by_name:
            self.err(self.decl.name.span, f"creature '{self.decl.name.name}' has no bodies")
        for extra in roots[1:]:
            self.err(
                extra.attach.span,
                f"a second root: body '{extra.name.name}' is also free or fixed, but "
                f"'{roots[0].name.name}' is the root; hang it from a parent with "
                "'on PARENT via KIND JOINT'",
            )
        children: dict[str, list[ast.BodyDecl]] = {}
        for b in by_name.values():
            if isinstance(b.attach, ast.AttachJoint):
                parent = b.attach.parent
                if parent.name not in by_name:
                    self.err(
                        parent.span,
                        f"unknown parent body '{parent.name}'{did_you_mean(parent.name, by_name)}",
                    )
                    continue
                if parent.name == b.name.name:
                    self.err(parent.span, f"body '{b.name.name}' cannot hang from itself")
                    continue
                children.setdefault(parent.name, []).append(b)
        order: list[ast.BodyDecl] = []
        seen: set[str] = set()
        stack = list(reversed(roots[:1]))
        while stack:
            b = stack.pop()
            if b.name.name in seen:
                continue
            seen.add(b.name.name)
            order.append(b)
            stack.extend(reversed(children.get(b.name.name, [])))
        # Bodies not reached from the root: in a cycle, or below a missing parent.
        for b in by_name.values():
            if b.name.name in seen or not isinstance(b.attach, ast.AttachJoint):
                continue
            chain = [b.name.name]
            node = b
            while isinstance(node.attach, ast.AttachJoint) and node.attach.parent.name in by_name:
                node = by_name[node.attach.parent.name]
                if node.name.name in chain:
                    loop = chain[chain.index(node.name.name) :] + [node.name.name]
                    if b.name.name == min(loop):  # report each cycle once
                        self.err(
                            b.name.span,
                            "bodies form a cycle: " + " -> ".join(loop) + "; a creature is a tree",
                        )
                    break
                chain.append(node.name.name)
        return order

    def build_tree(
        self, order: list[ast.BodyDecl]
    ) -> tuple[list[Body], list[Joint], list[float], list[float]]:
        bodies: list[Body] = []
        joints: list[Joint] = []
        q0: list[float] = []
        v0: list[float] = []
        by_name: dict[str, Body] = {}
        for decl in order:
            props = self.body_props(decl)
            body = self.body(decl, props, by_name)
            joint, q_init, v_init = self.joint(decl, props, body, by_name, len(q0), len(v0))
            by_name[body.name] = body
            bodies.append(body)
            joints.append(joint)
            q0 += q_init
            v0 += v_init
        return bodies, joints, q0, v0

    def body_props(self, decl: ast.BodyDecl) -> dict[str, ast.Prop]:
        props: dict[str, ast.Prop] = {}
        for p in decl.props:
            key = p.key.name
            if key not in BODY_PROPS:
                self.err(
                    p.key.span,
                    f"unknown body property '{key}'"
                    + (did_you_mean(key, BODY_PROPS) or "; a body takes " + ", ".join(BODY_PROPS)),
                )
            elif key in props:
                self.err(p.key.span, f"'{key}' is given twice for body '{decl.name.name}'")
            else:
                props[key] = p
        return props

    def body(
        self, decl: ast.BodyDecl, props: dict[str, ast.Prop], parents: dict[str, Body]
    ) -> Body:
        name = decl.name.name
        self.declare(decl.name, "body")
        mass = 1.0
        if "mass" not in props:
            self.err(decl.name.span, f"body '{name}' needs a mass, e.g. 'mass 1.5 kg'")
        else:
            m = self.one_scalar(props["mass"], "mass", "the mass")
            if m is not None and m <= 0:
                self.err(props["mass"].value.span, f"the mass of body '{name}' must be positive")
            elif m is not None:
                mass = m

        length = None
        if "length" in props:
            length = self.one_scalar(props["length"], "length", "the link length")
            if length is not None and length <= 0:
                self.err(props["length"].value.span, "a link length must be positive")
                length = None

        direction: Vec3 = (0.0, 0.0, -1.0)
        if "direction" in props:
            p = props["direction"]
            if isinstance(p.value, ast.One):
                direction = self.unit_vector(p.value.value, "the link direction") or direction

        com: Vec3 = (0.0, 0.0, 0.0)
        if "com" in props:
            p = props["com"]
            if isinstance(p.value, ast.One) and isinstance(p.value.value, ast.Vector):
                com = self.point(p.value.value, "the mass centre") or com
            else:
                along = self.one_scalar(p, "length", "the mass centre (distance along the link)")
                if along is not None:
                    com = (along * direction[0], along * direction[1], along * direction[2])

        inertia = self.inertia(decl, props.get("inertia"), mass)
        shape = self.shape(props.get("shape"), length, mass)
        color = None
        if "color" in props:
            p = props["color"]
            if isinstance(p.value, ast.One) and isinstance(p.value.value, ast.String):
                color = p.value.value.text
                if not (len(color) == 7 and color[0] == "#" and _is_hex(color[1:])):
                    self.err(p.value.span, 'a colour is written as "#rrggbb", e.g. "#c08040"')
                    color = None
            else:
                self.err(p.value.span, 'a colour is a string such as "#c08040"')
        parent = decl.attach.parent.name if isinstance(decl.attach, ast.AttachJoint) else None
        joint_name = decl.attach.joint.name if isinstance(decl.attach, ast.AttachJoint) else "root"
        return Body(
            name, parent, joint_name, mass, com, inertia, length, direction, shape, color, decl.span
        )

    def inertia(self, decl: ast.BodyDecl, prop: ast.Prop | None, mass: float) -> Mat3:
        name = decl.name.name
        fallback: Mat3 = ((1e-3, 0.0, 0.0), (0.0, 1e-3, 0.0), (0.0, 0.0, 1e-3))
        if prop is None:
            self.err(
                decl.name.span,
                f"body '{name}' needs an inertia about its mass centre, e.g. "
                + ("'inertia 0.01 kg*m^2'" if self.planar else "'inertia (0.1, 0.1, 0.05) kg*m^2'"),
            )
            return fallback
        if not isinstance(prop.value, ast.One):
            self.err(prop.value.span, "'inertia' takes one value")
            return fallback
        value = prop.value.value
        if self.planar:
            i = self.scalar(value, "moment of inertia", "the inertia of a planar body (about y)")
            if i is None:
                return fallback
            if i <= 0:
                self.err(value.span, f"the inertia of body '{name}' must be positive")
                return fallback
            # Only the moment about y acts in a planar model; the others are set equal so
            # that exports (MJCF, URDF) carry a valid tensor.
            return ((i, 0.0, 0.0), (0.0, i, 0.0), (0.0, 0.0, i))
        if isinstance(value, ast.Vector) and value.items and isinstance(value.items[0], ast.Vector):
            rows = []
            for row in value.items:
                r = (
                    self.vector(row, "moment of inertia", 3, "a row of the inertia matrix")
                    if not value.unit
                    else None
                )
                if value.unit:
                    self.err(
                        value.unit_span or value.span,
                        "put the unit on each number of a 3x3 inertia",
                    )
                    return fallback
                if r is None:
                    return fallback
                rows.append(r)
            if len(rows) != 3:
                self.err(
                    value.span, "a full inertia is a 3x3 matrix ((Ixx, Ixy, Ixz), (...), (...))"
                )
                return fallback
            mat = np.array(rows)
            if not np.allclose(mat / _scale(mat), mat.T / _scale(mat), rtol=1e-9, atol=1e-12):
                self.err(value.span, f"the inertia matrix of body '{name}' must be symmetric")
                return fallback
        else:
            diag = self.vector(value, "moment of inertia", 3, "the inertia (Ixx, Iyy, Izz)")
            if diag is None:
                return fallback
            mat = np.diag(diag)
        with np.errstate(over="ignore"):
            eig = np.linalg.eigvalsh(mat / _scale(mat)) * _scale(mat)
        if not np.isfinite(eig).all():
            self.err(value.span, f"the inertia of body '{name}' is too large")
            return fallback
        if eig.min() <= 0:
            self.err(
                value.span,
                f"the inertia of body '{name}' is not positive definite (principal moments "
                f"{', '.join(f'{e:.3g}' for e in eig)}); every principal moment must be > 0",
            )
            return fallback
        a, b, c = sorted(eig)
        if a / c + b / c < 1 - 1e-9:
            self.err(
                value.span,
                f"the inertia of body '{name}' breaks the triangle inequality: principal moments "
                f"{a:.3g} + {b:.3g} < {c:.3g}, which no rigid body has",
            )
            return fallback
        return (
            (float(mat[0, 0]), float(mat[0, 1]), float(mat[0, 2])),
            (float(mat[1, 0]), float(mat[1, 1]), float(mat[1, 2])),
            (float(mat[2, 0]), float(mat[2, 1]), float(mat[2, 2])),
        )

    def shape(self, prop: ast.Prop | None, length: float | None, mass: float) -> Shape:
        if prop is None:
            if length:
                return Shape("capsule", (("r", 0.1 * length),))
            # A sphere of water of the body's mass.
            return Shape("sphere", (("r", (3 * mass / (4 * math.pi * 1000.0)) ** (1 / 3)),))
        default = Shape("sphere", (("r", 0.05),))
        value = prop.value.value if isinstance(prop.value, ast.One) else None
        if not isinstance(value, ast.Call):
            self.err(
                prop.value.span,
                "a shape is written as a call: " + ", ".join(f"{k}(...)" for k in SHAPES),
            )
            return default
        kind = value.func.name
        if kind not in SHAPES:
            self.err(
                value.func.span,
                f"unknown shape '{kind}'; use one of {', '.join(SHAPES)}{did_you_mean(kind, SHAPES)}",
            )
            return default
        keys = SHAPES[kind]
        if kind == "box" and self.planar:
            keys = ("x", "z")
        params: dict[str, float] = {}
        center: Vec3 = (0.0, 0.0, 0.0)
        positional = [a for a in value.args if a.keyword is None]
        if len(positional) > len(keys):
            self.err(value.span, f"{kind}() takes {len(keys)} sizes ({', '.join(keys)})")
            return default
        given: set[str] = set()  # written, even if wrong (then reported on its own)
        for key, arg in zip(keys, positional, strict=False):
            given.add(key)
            v = self.scalar(arg.value, "length", f"{kind} size '{key}'")
            if v is not None:
                params[key] = v
        for arg in value.args:
            if arg.keyword is None:
                continue
            name = arg.keyword.name
            if name not in (*keys, "center"):
                self.err(
                    arg.keyword.span,
                    f"{kind}() has no argument '{name}'; it takes {', '.join(keys)} and center",
                )
                continue
            if name in given:
                self.err(arg.keyword.span, f"'{name}' is given twice")
                continue
            given.add(name)
            if name == "center":
                center = self.point(arg.value, "the shape centre") or center
            else:
                v = self.scalar(arg.value, "length", f"{kind} size '{name}'")
                if v is not None:
                    params[name] = v
        for key, v in params.items():
            if v <= 0:
                self.err(value.span, f"{kind} size '{key}' must be positive")
        missing = [k for k in keys if k not in given]
        if missing:
            self.err(value.span, f"{kind}() needs {', '.join(missing)}")
        if missing or any(k not in params or params[k] <= 0 for k in keys):
            return default
        if kind == "box" and self.planar:
            params["y"] = min(params["x"], params["z"])
        return Shape(kind, tuple((k, params[k]) for k in SHAPES[kind]), center)

    def joint(
        self,
        decl: ast.BodyDecl,
        props: dict[str, ast.Prop],
        body: Body,
        bodies: dict[str, Body],
        q_start: int,
        v_start: int,
    ) -> tuple[Joint, list[float], list[float]]:
        attach = decl.attach
        origin: Vec3 = (0.0, 0.0, 0.0)
        parent = None
        if isinstance(attach, ast.AttachFree):
            kind, name, span = "free", "root", attach.span
        elif isinstance(attach, ast.AttachFixed):
            kind, name, span = "fixed", "root", attach.span
            if attach.at is not None:
                origin = self.point(attach.at, "the root's location") or origin
        else:
            kind, name, span = attach.kind.name, attach.joint.name, attach.joint.span
            parent = attach.parent.name
            if kind not in JOINT_KINDS:
                self.err(
                    attach.kind.span,
                    f"unknown joint kind '{kind}'; use one of {', '.join(JOINT_KINDS)}"
                    + did_you_mean(kind, JOINT_KINDS),
                )
                kind = "fixed"
            if self.planar and kind in ("gimbal", "ball"):
                self.err(
                    attach.kind.span,
                    f"a planar creature has no {kind} joints; use revolute joints about y",
                )
                kind = "fixed"
            self.declare(attach.joint, "joint")
            if kind == "fixed":
                kind = "weld"
            if attach.at is not None:
                origin = self.location(attach.at, bodies.get(parent))

        axes = self.joint_axes(decl, props, kind, body)
        if kind == "free":
            coord_names = ["x", "z", "pitch"] if self.planar else []
        elif kind in ("gimbal", "ball"):
            suffixes = [_axis_suffix(a, i) for i, a in enumerate(axes)]
            if len(set(suffixes)) < len(suffixes):  # e.g. axes x, y, x: number them all
                suffixes = [str(i + 1) for i in range(len(axes))]
            coord_names = [f"{name}_{s}" for s in suffixes]
        elif kind in ("revolute", "prismatic"):
            coord_names = [name]
        else:
            coord_names = []
        if kind in ("free", "gimbal", "ball"):
            for c in coord_names:
                self.declare(ast.Ident(c, span), "coordinate")

        motions = (
            ["slide", "slide", "hinge"]
            if kind == "free"
            else ["slide"]
            if kind == "prismatic"
            else ["hinge"] * len(coord_names)
        )
        free3d = kind == "free" and not self.planar
        initial, rates = self.initial_values(decl, props, coord_names, motions, free3d)
        limits = self.limits(props.get("limits"), coord_names, motions)
        dofs = tuple(
            Dof(
                name=c,
                joint=name,
                motion=motions[i],
                axis=axes[i],
                q_index=q_start + i,
                v_index=v_start + i,
                initial=initial[i],
                initial_rate=rates[i],
                limits=limits[i],
            )
            for i, c in enumerate(coord_names)
        )
        nq, nv = (7, 6) if free3d else (len(dofs), len(dofs))
        joint = Joint(name, kind, parent, body.name, origin, dofs, q_start, nq, v_start, nv, span)
        return joint, list(initial), list(rates)

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
            if parent.length is None:
                self.err(value.span, f"'at tip' needs a length on the {whose} '{parent.name}'")
            return parent.tip
        return self.point(value, f"the {what}") or (0.0, 0.0, 0.0)

    def joint_axes(
        self, decl: ast.BodyDecl, props: dict[str, ast.Prop], kind: str, body: Body
    ) -> list[Vec3]:
        x, y, z = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)
        axis_prop, axes_prop = props.get("axis"), props.get("axes")
        if kind == "free":
            for p in (axis_prop, axes_prop):
                if p is not None:
                    self.err(p.key.span, "a free root has no axis")
            return [x, z, y] if self.planar else []
        if kind in ("weld", "fixed"):
            for p in (axis_prop, axes_prop):
                if p is not None:
                    self.err(p.key.span, "a fixed joint has no axis")
            return []
        if kind in ("revolute", "prismatic"):
            if axes_prop is not None:
                self.err(axes_prop.key.span, f"a {kind} joint has one 'axis', not 'axes'")
            if axis_prop is None:
                return [y if kind == "revolute" else body.direction]
            if self.planar and kind == "revolute":
                self.err(
                    axis_prop.key.span,
                    "in a planar creature every revolute joint turns about y; remove 'axis'",
                )
                return [y]
            if not isinstance(axis_prop.value, ast.One):
                self.err(axis_prop.value.span, "'axis' takes one vector")
                return [y]
            return [self.unit_vector(axis_prop.value.value, "the joint axis") or y]
        n = 2 if kind == "gimbal" else 3
        default = [x, y] if kind == "gimbal" else [x, y, z]
        if axis_prop is not None:
            self.err(
                axis_prop.key.span, f"a {kind} joint takes 'axes' (one vector each), not 'axis'"
            )
        if axes_prop is None:
            return default
        values = (
            axes_prop.value.values if isinstance(axes_prop.value, ast.Many)
            else (axes_prop.value.value,) if isinstance(axes_prop.value, ast.One) else ()
        )  # fmt: skip
        if len(values) != n:
            self.err(axes_prop.value.span, f"a {kind} joint has {n} axes, got {len(values)}")
            return default
        out = [self.unit_vector(v, "a joint axis") for v in values]
        if any(a is None for a in out):
            return default
        axes = [a for a in out if a is not None]
        for a, b in zip(axes, axes[1:], strict=False):
            if abs(sum(p * q for p, q in zip(a, b, strict=True))) > 1 - 1e-9:
                self.err(axes_prop.value.span, f"the axes of a {kind} joint must not be parallel")
                return default
        return axes

    def initial_values(
        self,
        decl: ast.BodyDecl,
        props: dict[str, ast.Prop],
        coords: list[str],
        motions: list[str],
        free3d: bool,
    ) -> tuple[list[float], list[float]]:
        init = [0.0] * len(coords)
        rates = [0.0] * len(coords)
        if free3d:
            return self.free3d_initial(props)
        for key, values, rate in (("initial", init, False), ("velocity", rates, True)):
            prop = props.get(key)
            if prop is None:
                continue
            if not coords:
                self.err(
                    prop.key.span, f"body '{decl.name.name}' has a fixed joint: it has no '{key}'"
                )
                continue
            if isinstance(prop.value, ast.One) and len(coords) == 1:
                v = self.scalar(
                    prop.value.value, _coord_kind(motions[0], rate), f"the {key} {coords[0]}"
                )
                values[0] = v if v is not None else 0.0
            elif isinstance(prop.value, ast.Assigns):
                for item in prop.value.items:
                    if item.target.name not in coords:
                        self.err(
                            item.target.span,
                            f"'{item.target.name}' is not a coordinate of this joint; "
                            f"it has {', '.join(coords)}{did_you_mean(item.target.name, coords)}",
                        )
                        continue
                    i = coords.index(item.target.name)
                    v = self.scalar(
                        item.value, _coord_kind(motions[i], rate), f"the {key} {coords[i]}"
                    )
                    values[i] = v if v is not None else 0.0
            else:
                self.err(
                    prop.value.span,
                    f"write '{key}' as one value for a one-coordinate joint, or as "
                    f"'{key} {coords[0]} = ...' naming each of {', '.join(coords)}",
                )
        return init, rates

    def free3d_initial(self, props: dict[str, ast.Prop]) -> tuple[list[float], list[float]]:
        pos = {"x": 0.0, "y": 0.0, "z": 0.0}
        ang = {"roll": 0.0, "pitch": 0.0, "yaw": 0.0}
        vel = dict.fromkeys(("vx", "vy", "vz", "wx", "wy", "wz"), 0.0)
        for key, table in (("initial", {**pos, **ang}), ("velocity", vel)):
            prop = props.get(key)
            if prop is None:
                continue
            if not isinstance(prop.value, ast.Assigns):
                self.err(
                    prop.value.span,
                    f"a 3D free root takes '{key} NAME = value, ...' with names from {', '.join(table)}",
                )
                continue
            for item in prop.value.items:
                n = item.target.name
                if n not in table:
                    self.err(
                        item.target.span,
                        f"'{n}' is not a coordinate of a 3D free root; use {', '.join(table)}{did_you_mean(n, table)}",
                    )
                    continue
                kind = (
                    "length"
                    if n in pos
                    else "angle"
                    if n in ang
                    else "velocity"
                    if n.startswith("v")
                    else "angular velocity"
                )
                v = self.scalar(item.value, kind, f"the {key} {n}")
                table[n] = v if v is not None else 0.0
            if key == "initial":
                pos.update({k: table[k] for k in pos})
                ang.update({k: table[k] for k in ang})
        qw, qx, qy, qz = _quat_from_rpy(ang["roll"], ang["pitch"], ang["yaw"])
        return [pos["x"], pos["y"], pos["z"], qw, qx, qy, qz], list(vel.values())

    def limits(
        self, prop: ast.Prop | None, coords: list[str], motions: list[str]
    ) -> list[tuple[float, float] | None]:
        out: list[tuple[float, float] | None] = [None] * len(coords)
        if prop is None:
            return out
        if not coords:
            self.err(prop.key.span, "this joint has no coordinates to limit")
            return out
        pairs: list[tuple[ast.Value, ast.Value, Span]] = []
        if isinstance(prop.value, ast.Range) and len(coords) == 1:
            pairs = [(prop.value.low, prop.value.high, prop.value.span)]
        else:
            values = (
                prop.value.values
                if isinstance(prop.value, ast.Many)
                else (prop.value.value,)
                if isinstance(prop.value, ast.One)
                else ()
            )
            if len(values) != len(coords) or not all(
                isinstance(v, ast.Vector) and len(v.items) == 2 for v in values
            ):
                self.err(
                    prop.value.span,
                    "write limits as 'limits LOW to HIGH' for a one-coordinate joint, or as one "
                    f"(low, high) pair per coordinate ({', '.join(coords)})",
                )
                return out
            pairs = [(v.items[0], v.items[1], v.span) for v in values if isinstance(v, ast.Vector)]
        for i, (lo_v, hi_v, span) in enumerate(pairs):
            kind = _coord_kind(motions[i], False)
            lo = self.scalar(lo_v, kind, "a lower limit")
            hi = self.scalar(hi_v, kind, "an upper limit")
            if lo is None or hi is None:
                continue
            if lo >= hi:
                self.err(span, "a joint's lower limit must be below its upper limit")
                continue
            out[i] = (lo, hi)
        return out

    # ---------------------------------------------------------- actuators, contacts
    def actuator(self, decl: ast.ActuatorDecl, dofs: dict[str, Dof]) -> Actuator | None:
        self.declare(decl.name, "actuator")
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
        if dof is None:
            self.err(
                decl.coordinate.span,
                f"actuator '{decl.name.name}' is on '{decl.coordinate.name}', which is not a "
                f"joint coordinate{did_you_mean(decl.coordinate.name, dofs)}",
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
                self.err(
                    arg.value.span,
                    f"'{key}' of a {kind} on the {joint_desc} must be {article(want)} {want} "
                    f"({unit_hint(want)}); this is {article(wrong)} {wrong}, which belongs on a "
                    f"{'sliding' if rotary else 'revolute'} joint",
                )
                continue
            v = self.scalar(arg.value, want, f"'{key}'")
            if v is None:
                continue
            if key in ("k", "b", "kp", "kv", "max") and v < 0:
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
        self.declare(decl.name, "contact")
        body = bodies.get(decl.body.name)
        if body is None:
            self.err(
                decl.body.span,
                f"contact '{decl.name.name}' is on an unknown body '{decl.body.name}'{did_you_mean(decl.body.name, bodies)}",
            )
            return None
        point = (
            self.location(decl.at, body, contact=True) if decl.at is not None else (0.0, 0.0, 0.0)
        )
        return Contact(decl.name.name, body.name, point, decl.span)

    # ---------------------------------------------------------- ground
    def ground(self, block: ast.BlockDecl) -> Ground | None:
        seen: dict[str, ast.Prop] = {}
        terrain: list[Terrain] = []
        normal: SpringDamper | Pad | None = None
        tangent = torsion = None
        friction: float | None = None
        for p in block.props:
            key = p.key.name
            if key not in GROUND_PROPS:
                self.err(
                    p.key.span,
                    f"unknown ground property '{key}'"
                    + (
                        did_you_mean(key, GROUND_PROPS)
                        or f"; the ground takes {', '.join(GROUND_PROPS)}"
                    ),
                )
                continue
            if key in seen and key != "terrain":
                self.err(p.key.span, f"'{key}' is given twice in the ground block")
                continue
            seen[key] = p
            value = p.value.value if isinstance(p.value, ast.One) else None
            if key == "friction":
                if isinstance(value, ast.NameValue) and value.ident.name == "none":
                    friction = None
                elif value is not None:
                    friction = self.scalar(value, "dimensionless", "the friction coefficient")
                    if friction is not None and friction <= 0:
                        self.err(
                            value.span,
                            "a friction coefficient must be positive; write 'friction none' for no slip",
                        )
                else:
                    self.err(
                        p.value.span,
                        "write 'friction none' (no slip) or a coefficient such as 'friction 0.8'",
                    )
                continue
            if not isinstance(value, ast.Call):
                self.err(p.value.span, _ground_help(key))
                continue
            if key == "terrain":
                t = self.terrain(value)
                if t is not None:
                    terrain.append(t)
                continue
            rotary = key == "torsion"
            if key == "torsion" and self.planar:
                self.err(
                    p.key.span,
                    "a planar creature has no torsional ground spring (it turns about the normal only in 3D)",
                )
                continue
            if value.func.name == "pad" and key == "normal":
                args = self.kwargs(
                    value,
                    {"k": "force", "thickness": "length", "b": "linear damping"},
                    ("k", "thickness"),
                )
                if args is not None:
                    normal = Pad(args["k"], args["thickness"], args.get("b", 0.0))
                continue
            if value.func.name != "spring":
                self.err(value.func.span, _ground_help(key))
                continue
            args = self.kwargs(
                value,
                {
                    "k": "angular stiffness" if rotary else "linear stiffness",
                    "b": "angular damping" if rotary else "linear damping",
                },
                ("k",),
            )
            if args is None:
                continue
            sd = SpringDamper(args["k"], args.get("b", 0.0))
            if key == "normal":
                normal = sd
            elif key == "tangent":
                tangent = sd
            else:
                torsion = sd
        if any(t.kind == "slope" for t in terrain) and len(terrain) > 1:
            self.err(
                block.name.span,
                "a slope is the whole ground: it cannot be combined with other terrain",
            )
        for key in ("normal", "tangent"):
            if key not in seen:
                what, forms = _GROUND_HELP[key]
                self.err(block.name.span, f"the ground needs {what}: {forms}")
        if normal is None or tangent is None:
            return None
        return Ground(normal, tangent, torsion, friction, tuple(terrain), block.span)

    def kwargs(
        self, call: ast.Call, kinds: dict[str, str], required: tuple[str, ...]
    ) -> dict[str, float] | None:
        out: dict[str, float] = {}
        given: set[str] = set()
        ok = True
        for arg in call.args:
            if arg.keyword is None or arg.keyword.name not in kinds:
                word = arg.keyword.name if arg.keyword else "a positional argument"
                self.err(
                    arg.span,
                    f"{call.func.name}() takes {', '.join(k + ' = ...' for k in kinds)}, not {word}",
                )
                ok = False
                continue
            if arg.keyword.name in given:
                self.err(arg.keyword.span, f"'{arg.keyword.name}' is given twice")
                ok = False
                continue
            given.add(arg.keyword.name)
            v = self.scalar(arg.value, kinds[arg.keyword.name], f"'{arg.keyword.name}'")
            if v is None:
                ok = False
                continue
            if v < 0 or (v == 0 and arg.keyword.name in ("thickness", "height")):
                self.err(arg.value.span, f"'{arg.keyword.name}' must be positive")
                ok = False
                continue
            out[arg.keyword.name] = v
        for key in required:
            if key not in out and ok:
                self.err(call.span, f"{call.func.name}() needs '{key}'")
                ok = False
        return out if ok else None

    def terrain(self, call: ast.Call) -> Terrain | None:
        kinds = {
            "step": ({"x": "length", "height": "length"}, ("x", "height")),
            "box": (
                {
                    "x0": "length",
                    "x1": "length",
                    "y0": "length",
                    "y1": "length",
                    "height": "length",
                },
                ("x0", "x1", "height") if self.planar else ("x0", "x1", "y0", "y1", "height"),
            ),
            # The whole ground tilted about y, rising towards +x.
            "slope": ({"angle": "angle"}, ("angle",)),
        }
        if call.func.name not in kinds:
            self.err(
                call.func.span,
                f"unknown terrain '{call.func.name}'; use step(x = ..., height = ...), box(x0 = ..., x1 = ..., height = ...) or slope(angle = ...){did_you_mean(call.func.name, kinds)}",
            )
            return None
        arg_kinds, required = kinds[call.func.name]
        args = self.kwargs_signed(call, arg_kinds, required)
        if args is None:
            return None
        if call.func.name == "slope" and not abs(args["angle"]) < math.radians(80):
            self.err(call.span, "a slope's angle must be between -80 deg and 80 deg")
            return None
        if call.func.name == "box":
            if args["x1"] <= args["x0"] or args.get("y1", 1.0) <= args.get("y0", 0.0):
                self.err(call.span, "a box needs x0 < x1 (and y0 < y1)")
                return None
            args.setdefault("y0", -1e3)
            args.setdefault("y1", 1e3)
        return Terrain(call.func.name, tuple(sorted(args.items())), call.span)

    def kwargs_signed(
        self, call: ast.Call, kinds: dict[str, str], required: tuple[str, ...]
    ) -> dict[str, float] | None:
        out: dict[str, float] = {}
        for arg in call.args:
            if arg.keyword is None or arg.keyword.name not in kinds:
                self.err(
                    arg.span, f"{call.func.name}() takes {', '.join(k + ' = ...' for k in kinds)}"
                )
                return None
            if arg.keyword.name in out:
                self.err(arg.keyword.span, f"'{arg.keyword.name}' is given twice")
                return None
            v = self.scalar(arg.value, kinds[arg.keyword.name], f"'{arg.keyword.name}'")
            if v is None:
                return None
            out[arg.keyword.name] = v
        missing = [k for k in required if k not in out]
        if missing:
            self.err(call.span, f"{call.func.name}() needs {', '.join(missing)}")
            return None
        if out.get("height", 1.0) <= 0:
            self.err(call.span, "a terrain height must be positive")
            return None
        return out

    # ---------------------------------------------------------- legs
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
        foot = None
        aliases: list[tuple[str, str]] = []
        seen: set[str] = set()
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
                        continue
                    if ident.name not in joint_names:
                        self.err(
                            ident.span,
                            f"unknown joint '{ident.name}'{did_you_mean(ident.name, joint_names)}",
                        )
                    else:
                        leg_joints.append(ident.name)
            elif key == "foot":
                ident = (
                    self.name_of(p.value.value, "a leg's foot")
                    if isinstance(p.value, ast.One)
                    else None
                )
                if ident is None:
                    if not isinstance(p.value, ast.One):
                        self.err(p.value.span, "a leg has one foot contact: 'foot toe'")
                elif ident.name not in contact_by:
                    self.err(
                        ident.span,
                        f"unknown contact '{ident.name}'; declare it with 'contact {ident.name} on BODY at tip'{did_you_mean(ident.name, contact_by)}",
                    )
                else:
                    foot = ident.name
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
                    if target.name not in referable:
                        self.err(
                            target.span,
                            f"unknown name '{target.name}'; an alias names an actuator, joint, coordinate, contact or body{did_you_mean(target.name, referable)}",
                        )
                        continue
                    aliases.append((item.target.name, target.name))
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
        if leg_joints[0] not in chain:
            self.err(
                decl.name.span,
                f"the foot '{foot}' of leg '{decl.name.name}' is not below its first joint '{leg_joints[0]}'",
            )
        return Leg(decl.name.name, tuple(leg_joints), foot, tuple(aliases), decl.span)


# What each ground property is, and how it is written.
_GROUND_HELP = {
    "normal": (
        "the vertical spring",
        "'normal spring(k = 1.2e4 N/m, b = 150 N*s/m)' or the paw pad of eq. (6), 'normal pad(k = 250 N, thickness = 1 cm, b = 100 N*s/m)'",
    ),
    "tangent": ("the tangential springs", "'tangent spring(k = 8e3 N/m, b = 120 N*s/m)'"),
    "torsion": (
        "the torsional spring about the normal",
        "'torsion spring(k = 5 N*m/rad, b = 0.5 N*m*s/rad)'",
    ),
    "terrain": (
        "a terrain feature",
        "'terrain step(x = 2 m, height = 0.1 m)', 'terrain box(x0 = 3 m, x1 = 3.3 m, height = 0.2 m)' or 'terrain slope(angle = 10 deg)'",
    ),
}


def _ground_help(key: str) -> str:
    what, forms = _GROUND_HELP[key]
    return f"write {what} as {forms}"


def _scale(mat: np.ndarray) -> float:
    """The largest magnitude in a matrix (1 if all zero): divide by it to compute safely."""
    return float(np.abs(mat).max()) or 1.0


def _coord_kind(motion: str, rate: bool) -> str:
    if motion == "hinge":
        return "angular velocity" if rate else "angle"
    return "velocity" if rate else "length"


def _axis_suffix(axis: Vec3, index: int) -> str:
    for name, unit in (("x", (1.0, 0.0, 0.0)), ("y", (0.0, 1.0, 0.0)), ("z", (0.0, 0.0, 1.0))):
        if axis == unit:
            return name
    return str(index + 1)


def _quat_from_rpy(roll: float, pitch: float, yaw: float) -> tuple[float, float, float, float]:
    """Quaternion (w, x, y, z) of R = Rz(yaw) Ry(pitch) Rx(roll)."""
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return (
        cr * cp * cy + sr * sp * sy,
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
    )


def _is_hex(text: str) -> bool:
    return all(c in "0123456789abcdefABCDEF" for c in text)
