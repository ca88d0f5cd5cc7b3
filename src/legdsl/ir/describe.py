"""A person-readable description of a model: the text of ``legdsl show``."""

from __future__ import annotations

import math

from legdsl.figures import figure, figures
from legdsl.ir.model import Model, Pad, Vec3


def _vec(v: Vec3, planar: bool) -> str:
    parts = (v[0], v[2]) if planar else v
    return f"{figures(parts)} m"


def _joint_text(model: Model, body_name: str) -> str:
    joint = next(j for j in model.joints if j.child == body_name)
    if joint.kind == "free":
        coords = "x, z, pitch" if model.planar else "x, y, z + quaternion (6 DOF)"
        return f"free root [{coords}]"
    if joint.kind == "fixed":
        return "fixed to the world"
    if joint.kind == "weld":
        return f"via fixed {joint.name} (0 DOF)"
    coords = ", ".join(d.name for d in joint.dofs)
    return f"via {joint.kind} {joint.name} [{coords}] ({joint.nv} DOF)"


def describe_model(model: Model) -> str:
    kind = "planar" if model.planar else "spatial"
    g = -model.gravity[2]
    lines = [
        f"creature {model.name} ({kind}) from {model.source}",
        f"  {model.nv} DOF, total mass {figure(model.total_mass)} kg, gravity {figure(g)} m/s^2",
        "",
        "link tree:",
    ]
    children: dict[str | None, list[str]] = {}
    for b in model.bodies:
        children.setdefault(b.parent, []).append(b.name)

    def walk(name: str, prefix: str, last: bool, root: bool) -> None:
        body = model.body(name)
        branch = "" if root else ("`-- " if last else "|-- ")
        length = f", length {figure(body.length)} m" if body.length else ""
        lines.append(
            f"  {prefix}{branch}{name}  {_joint_text(model, name)}  {figure(body.mass)} kg{length}"
        )
        kids = children.get(name, [])
        for i, kid in enumerate(kids):
            walk(
                kid,
                prefix + ("" if root else ("    " if last else "|   ")),
                i == len(kids) - 1,
                False,
            )

    for root in children.get(None, []):
        walk(root, "", True, True)

    lines += ["", f"coordinates ({model.nq} positions, {model.nv} velocities):"]
    lines.append("  q = (" + ", ".join(model.q_names) + ")")
    if model.q_names != model.v_names:
        lines.append("  v = (" + ", ".join(model.v_names) + ")")
    if model.legs:
        lines += ["", "legs:"]
        for leg in model.legs:
            alias = (
                "; aliases " + ", ".join(f"{a} = {t}" for a, t in leg.aliases)
                if leg.aliases
                else ""
            )
            lines.append(f"  {leg.name}: joints {', '.join(leg.joints)}; foot {leg.foot}{alias}")
    if model.contacts:
        lines += ["", "contacts:"]
        for c in model.contacts:
            lines.append(f"  {c.name} on {c.body} at {_vec(c.point, model.planar)}")
    if model.actuators:
        lines += ["", "actuators:"]
        for a in model.actuators:
            params = ", ".join(
                f"{k} = {math.degrees(v):.4g} deg"
                if a.rotary and k in ("rest", "setpoint")
                else f"{k} = {v:.4g}"
                for k, v in a.params
            )
            limit = f", max {a.max:.4g}" if a.max is not None else ""
            lines.append(f"  {a.name}: {a.kind} on {a.dof} ({params}{limit})")
    if model.ground is not None:
        gr = model.ground
        friction = "no slip" if gr.friction is None else f"friction {gr.friction:g}"
        terrain = "; terrain " + ", ".join(t.kind for t in gr.terrain) if gr.terrain else ""
        normal = (
            f"paw pad of eq. (6) ({gr.normal.k:g} N, {gr.normal.thickness * 100:g} cm)"
            if isinstance(gr.normal, Pad)
            else f"linear normal spring ({gr.normal.k:g} N/m)"
        )
        lines += ["", f"ground: {normal}, {friction}{terrain}"]
    if model.controllers:
        lines += ["", "controllers:"]
        for ctl in model.controllers:
            lines.append(
                f"  {ctl.name}: states {' -> '.join(ctl.state_names)} (starts in {ctl.start})"
            )
    if model.scenes:
        lines += ["", "scenes (legdsl run FILE --scene NAME):"]
        for scene in model.scenes:
            changes = "".join(f", {w.controller} at {w.t:g} s" for w in scene.switches)
            time = f" for {scene.duration:g} s" if scene.duration is not None else ""
            lines.append(f"  {scene.name}: {scene.controller}{changes}{time}")
    return "\n".join(lines) + "\n"
