"""The joint that hangs a body from its parent (or the root's free or fixed attachment):
its kind, location and axes, the coordinates it adds, their initial values and rates
(a 3D free root's as position and roll, pitch, yaw) and their limits."""

from __future__ import annotations

import contextlib
import difflib
import math

from legdsl.check.scope import CreaturePart, Scope
from legdsl.check.values import did_you_mean, written_unit
from legdsl.ir.model import (
    FREE_3D_Q_NAMES,
    FREE_3D_V_NAMES,
    Body,
    Dof,
    Joint,
    Stop,
    Vec3,
    axes_spread,
)
from legdsl.lang import ast
from legdsl.lang.errors import Span
from legdsl.lang.units import KINDS, UnitError, parse_unit

JOINT_KINDS = ("revolute", "prismatic", "gimbal", "ball", "fixed")
# What other tools name these kinds (MuJoCo's hinge and slide, URDF's continuous...): said so,
# and checked on as the kind meant.
KIND_SYNONYMS = {"hinge": "revolute", "continuous": "revolute", "pin": "revolute",
                 "slide": "prismatic", "slider": "prismatic", "linear": "prismatic",
                 "spherical": "ball", "universal": "gimbal"}  # fmt: skip


STOP_EXAMPLE = {
    "hinge": "'stop k = 2000 N*m/rad, b = 20 N*m*s/rad'",
    "slide": "'stop k = 1e5 N/m, b = 500 N*s/m'",
}


class JointChecker(CreaturePart):
    """Checks the attachment of a body and the joint properties given in its block."""

    def __init__(self, scope: Scope):
        super().__init__(scope)
        self.stops: list[Stop] = []  # of every joint checked, in tree order
        # each 'initial' value read: its coordinate, kind, value and span (magnitudes.py's)
        self.given: list[tuple[str, str, float, Span]] = []

    def scalar(self, value: ast.Value, kind: str, what: str) -> float | None:
        v = super().scalar(value, kind, what)
        if v is not None and what.startswith("the initial "):
            self.given.append((what.removeprefix("the initial "), kind, v, value.span))
        return v

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
                meant = KIND_SYNONYMS.get(kind.lower())
                self.err(
                    attach.kind.span,
                    f"unknown joint kind '{kind}'; use one of {', '.join(JOINT_KINDS)}"
                    + (f"; legdsl calls a {kind} joint '{meant}'" if meant
                       else did_you_mean(kind, JOINT_KINDS)),
                )  # fmt: skip
                # Checked on as the kind it most likely means, so that its coordinate (which
                # actuators and legs name) exists; failing that, as fixed.
                likely = [k for k in JOINT_KINDS if not (self.planar and k in ("gimbal", "ball"))]
                close = [meant] if meant in likely else difflib.get_close_matches(kind, likely, n=1)
                kind = close[0] if close else "fixed"
                if not close:
                    self.unsettled.add(attach.joint.name)
            if self.planar and kind in ("gimbal", "ball"):
                self.err(
                    attach.kind.span,
                    f"a planar creature has no {kind} joints; use revolute joints about y",
                )
                kind = "fixed"
                self.unsettled.add(attach.joint.name)
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
            # a 3D root's position coordinates are named too (q.x ... q.qz, a law's x)
            for c in coord_names or (FREE_3D_Q_NAMES if kind == "free" else ()):
                self.declare(ast.Ident(c, span), "coordinate")
        if kind == "free" and not self.planar:  # and its speeds (v.vx ... v.wz)
            for c in FREE_3D_V_NAMES:
                self.declare(ast.Ident(c, span), "root's velocity")

        motions = (
            ["slide", "slide", "hinge"]
            if kind == "free"
            else ["slide"]
            if kind == "prismatic"
            else ["hinge"] * len(coord_names)
        )
        free3d = kind == "free" and not self.planar
        initial, rates = self.initial_values(decl, props, coord_names, motions, free3d)
        if kind == "ball" and axes_spread(axes, initial) < 1e-6:
            where = props.get("axes") or props.get("initial")
            self.err(
                where.value.span if where is not None else span,
                f"ball joint '{name}' is in gimbal lock at its initial angles: its three axes "
                "lie in one plane (axes x, y, x with the middle angle 0 turn about x twice), so "
                "it cannot turn across that plane and its dynamics divide by zero; give it "
                f"axes at right angles, such as x, y, z, or start it with 'initial "
                f"{coord_names[1]} = 30 deg'",
            )
        limits = self.limits(props.get("limits"), coord_names, motions)
        stop = self.stop(props.get("stop"), props.get("limits"), limits, motions)
        self.initial_within_limits(props.get("initial"), coord_names, motions, initial, limits)
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
        if stop is not None:
            k, b, span, units = stop
            self.stops += [
                Stop(d.name, d.q_index, d.v_index, *d.limits, k, b, span, units)
                for d in dofs
                if d.limits is not None
            ]
        nq, nv = (7, 6) if free3d else (len(dofs), len(dofs))
        joint = Joint(name, kind, parent, body.name, origin, dofs, q_start, nq, v_start, nv, span)
        return joint, list(initial), list(rates)

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
                other = ", ".join(("(1, 0, 0)", "(0, 1, 0)", "(0, 0, 1)")[:n])
                self.err(
                    axes_prop.value.span,
                    f"the axes of a {kind} joint must not be parallel: each turns it about a "
                    f"direction of its own; give each axis one not parallel to the one before "
                    f"it, as in 'axes {other}'",
                )
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
                seen: set[str] = set()
                for item in prop.value.items:
                    if self.given_twice(item, key, seen):
                        continue
                    if item.target.name not in coords:
                        n = item.target.name
                        hint = (  # a 3D root's velocity names, vx..., on a planar joint
                            f"; a velocity is named by its coordinate: write '{key} {n[1:]} = ...'"
                            if rate and n[:1] == "v" and n[1:] in coords
                            else did_you_mean(n, coords)
                        )
                        self.err(
                            item.target.span,
                            f"'{n}' is not a coordinate of this joint; "
                            f"it has {', '.join(coords)}{hint}",
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

    def initial_within_limits(
        self,
        prop: ast.Prop | None,
        coords: list[str],
        motions: list[str],
        initial: list[float],
        limits: list[tuple[float, float] | None],
    ) -> None:
        """A joint written to start outside its own range is a slip (a sign, a unit)."""
        if prop is None or not len(coords) == len(motions) == len(initial) == len(limits):
            return  # a 3D free root (7 numbers for 6 motions) has no limits
        for c, m, q, lim in zip(coords, motions, initial, limits, strict=True):
            if lim is None or lim[0] - 1e-12 <= q <= lim[1] + 1e-12:
                continue
            show = (
                (lambda v: f"{math.degrees(v):g} deg") if m == "hinge" else (lambda v: f"{v:g} m")
            )
            self.err(
                prop.value.span,
                f"the initial {c}, {show(q)}, is outside its limits {show(lim[0])} to "
                f"{show(lim[1])}; start it within them or widen the limits",
            )

    def given_twice(self, item: ast.Assign, key: str, seen: set[str]) -> bool:
        """A coordinate named twice in one 'initial' or 'velocity': the second would win unseen."""
        name = item.target.name
        if name in seen:
            self.err(
                item.target.span,
                f"'{name}' is given twice in '{key}'; give each coordinate once",
            )
            return True
        seen.add(name)
        return False

    def free3d_initial(self, props: dict[str, ast.Prop]) -> tuple[list[float], list[float]]:
        pos = {"x": 0.0, "y": 0.0, "z": 0.0}
        ang = {"roll": 0.0, "pitch": 0.0, "yaw": 0.0}
        vel = dict.fromkeys(FREE_3D_V_NAMES, 0.0)
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
            seen_root: set[str] = set()
            for item in prop.value.items:
                n = item.target.name
                if self.given_twice(item, key, seen_root):
                    continue
                if n not in table:
                    other = "velocity" if key == "initial" else "initial"
                    self.err(
                        item.target.span,
                        f"'{n}' is not a coordinate of a 3D free root; use {', '.join(table)}"
                        + (
                            f"; '{n}' is {'a velocity' if n in vel else 'a position or angle'}: "
                            f"write it as '{other} {n} = ...'"
                            if n in vel or n in {**pos, **ang}
                            else did_you_mean(n, table)
                        ),
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

    def stop(
        self,
        prop: ast.Prop | None,
        limits_prop: ast.Prop | None,
        limits: list[tuple[float, float] | None],
        motions: list[str],
    ) -> tuple[float, float, Span, tuple[str, str]] | None:
        """``stop k = STIFFNESS, b = DAMPING``: the joint's limits are mechanical stops (with
        k's and b's units as written, the SI one where b is left out)."""
        if prop is None:
            return None
        if limits_prop is None:
            self.err(prop.key.span, "a stop needs the joint's limits: add 'limits LOW to HIGH'")
            return None
        if not isinstance(prop.value, ast.Assigns):
            self.err(prop.value.span, f"write the stop as {STOP_EXAMPLE[motions[0]]}")
            return None
        found: dict[str, float] = {}
        hinge = motions[0] == "hinge"
        units = {key: KINDS[f"{'angular' if hinge else 'linear'} {kind}"][1]
                 for key, kind in (("k", "stiffness"), ("b", "damping"))}  # fmt: skip
        for item in prop.value.items:
            key = item.target.name
            if key not in ("k", "b"):
                self.err(
                    item.target.span,
                    f"a stop takes k (stiffness) and b (damping), not '{key}'"
                    + did_you_mean(key, ["k", "b"]),
                )
                continue
            if key in found:
                self.err(item.target.span, f"'{key}' is given twice")
                continue
            kind = {"k": "stiffness", "b": "damping"}[key]
            kind = f"{'angular' if hinge else 'linear'} {kind}"
            v = self.scalar(item.value, kind, f"the stop's '{key}'")
            if v is None:
                continue
            if v < 0 or (key == "k" and v == 0):
                self.err(item.value.span, f"the stop's '{key}' must be positive")
                continue
            found[key] = v
            number = item.value
            while isinstance(number, ast.Neg):
                number = number.value
            if isinstance(number, ast.Number):  # a spelling parse_unit reads (else SI's)
                with contextlib.suppress(UnitError):
                    parse_unit(written_unit(number.text))
                    units[key] = written_unit(number.text)
        if "k" not in found:
            if not any(item.target.name == "k" for item in prop.value.items):
                example = STOP_EXAMPLE[motions[0]]
                self.err(prop.value.span, f"a stop needs its stiffness k: {example}")
            return None
        if any(m != motions[0] for m in motions) or not any(lim is not None for lim in limits):
            return None
        return found["k"], found.get("b", 0.0), prop.span, (units["k"], units["b"])

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
