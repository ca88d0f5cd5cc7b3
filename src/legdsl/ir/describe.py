"""A person-readable description of a model: the text of ``legdsl show``."""

from __future__ import annotations

import math

from legdsl.figures import figure, figures
from legdsl.ir.model import Model, Pad, Terrain, Vec3, setting_kind
from legdsl.ir.scene import Scene
from legdsl.lang.units import KINDS


def _setting(key: str, value: float, rotary: bool) -> str:
    """An actuator's setting in the unit a .leg file writes it in (an angle in degrees)."""
    kind = setting_kind("force" if key == "value" else key, rotary)
    if kind == "angle":
        return f"{math.degrees(value):.4g} deg"
    return f"{value:.4g} {KINDS[kind][1]}"


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


def _hip_points(model: Model) -> dict[str, Vec3]:
    """Each leg's hip point in the root body's frame (its first joint's origin and those of
    the joints between it and the root, at zero angles)."""
    joints = {j.name: j for j in model.joints}
    bodies = {b.name: b for b in model.bodies}
    out = {}
    for leg in model.legs:
        joint = joints[leg.joints[0]]
        point = list(joint.origin)
        while joint.parent is not None and bodies[joint.parent].parent is not None:
            joint = joints[bodies[joint.parent].joint]
            point = [a + b for a, b in zip(point, joint.origin, strict=True)]
        out[leg.name] = (point[0], point[1], point[2])
    return out


def _same_hips(hips: dict[str, Vec3]) -> list[str]:
    """A note for each set of legs of a spatial creature hanging from one point: a mirrored
    instance given the other side's point (mirror sagittal flips y: its HIP is written as for
    the left leg)."""
    at: dict[tuple[float, ...], list[str]] = {}
    for name, point in hips.items():
        at.setdefault(tuple(round(c, 9) for c in point), []).append(name)
    return [
        f"  note: legs {', '.join(names)} hang from the same point; a mirrored instance's "
        "point is written unmirrored ('mirror sagittal' turns y into -y)"
        for names in at.values()
        if len(names) > 1
    ]


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
        lines += ["", "legs (each hip's point in the root body's frame):"]
        hips = _hip_points(model)
        for leg in model.legs:
            alias = (
                "; aliases " + ", ".join(f"{a} = {t}" for a, t in leg.aliases)
                if leg.aliases
                else ""
            )
            hip = f"; hip at {_vec(hips[leg.name], model.planar)}"
            lines.append(
                f"  {leg.name}: joints {', '.join(leg.joints)}; foot {', '.join(leg.soles)}{hip}{alias}"
            )
        lines += [] if model.planar else _same_hips(hips)  # a planar creature's legs overlap
    if model.contacts:
        lines += ["", "contacts:"]
        for c in model.contacts:
            lines.append(f"  {c.name} on {c.body} at {_vec(c.point, model.planar)}")
    if model.actuators:
        lines += ["", "actuators:"]
        for a in model.actuators:
            params = ", ".join(f"{k} = {_setting(k, v, a.rotary)}" for k, v in a.params)
            limit = f", max {_setting('max', a.max, a.rotary)}" if a.max is not None else ""
            lines.append(f"  {a.name}: {a.kind} on {a.dof} ({params}{limit})")
    if model.ground is not None:
        gr = model.ground
        friction = "no slip" if gr.friction is None else f"friction {gr.friction:g}"
        terrain = (
            "; terrain " + ", ".join(_terrain(t, model.planar) for t in gr.terrain)
            if gr.terrain
            else ""
        )
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
            start = scene.controller if not scene.bands else _gait_table(model, scene)
            lines.append(f"  {scene.name}: {start}{changes}{time}")
    return "\n".join(lines) + "\n"


def _gait_table(model: Model, scene: Scene) -> str:
    """A scene's ``gait by speed { ... }`` as written, in the unit of its input's kind (its
    first band's controller alone would read as the only one run)."""
    dim = next((c.dim for ctl in model.controllers for c in ctl.inputs
                if c.name == scene.band_input), None)  # fmt: skip
    unit = next((u for d, u in KINDS.values() if d == dim), "")
    bands = "; ".join(b.text(unit) for b in scene.bands)
    table = f"gait by {scene.band_input} {{ {bands} }}"
    return table if scene.starts_by_band else f"{scene.controller}, then {table}"


_TERRAIN_ORDER = ("x", "x0", "x1", "y0", "y1", "height", "angle")  # as the docs write them


def _terrain(t: Terrain, planar: bool) -> str:
    """A terrain feature as read, in SI units: ``step(x = 2 m, height = 0.05 m)``; its angle
    in degrees; a planar box without the y extent it is given inside."""
    given = dict(t.params)
    keys = [k for k in _TERRAIN_ORDER if k in given and not (planar and k in ("y0", "y1"))]
    args = ", ".join(f"{k} = {math.degrees(given[k]):.4g} deg" if k == "angle"
                     else f"{k} = {given[k]:.4g} m" for k in keys)  # fmt: skip
    return f"{t.kind}({args})"
