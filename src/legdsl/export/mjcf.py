"""Write a checked ``Model`` as MJCF, MuJoCo's XML model format.

The mapping (every choice here is tested against MuJoCo itself in
``tests/export/test_export.py`` and ``tests/lower/test_mujoco_oracle.py``):

* One MuJoCo body per legdsl body, nested as the link tree, written at the
  zero configuration: ``pos`` is the joint origin in the parent frame and the
  body axes are the parent's (legdsl's frame rule), so no ``quat`` is needed.
* Each ``Dof`` becomes one MuJoCo joint named exactly as the legdsl
  coordinate: ``slide`` or ``hinge`` about the Dof's axis, at the body origin.
  A joint with several Dofs (gimbal, ball, the planar free root x, z, pitch)
  becomes several MuJoCo joints in the same body, in order. MuJoCo's
  ``mj_kinematics`` applies a body's joints one after the other, turning each
  joint's axis by the rotation accumulated so far, which is exactly legdsl's
  "chain of primitives applied in order".
* The 3D free root is ``<freejoint name="root"/>``: qpos (x, y, z, qw, qx, qy,
  qz), qvel (linear velocity in world axes, angular velocity in body axes),
  which is legdsl's convention, so coordinates map one to one by name.
* ``weld`` joints and a fixed root get no joint: the body is rigidly attached.
* Inertia is explicit (``inertiafromgeom="false"``): ``pos`` = mass centre,
  ``fullinertia`` about it in body axes. Drawing geoms come from
  ``Body.shape`` (a frustum is drawn as a capsule of its mean radius) and
  neither collide nor weigh anything. Each contact point gets a small sphere
  geom and a site, both named after the contact; the sphere sits on the
  contact's anchor pad (``mjpads.py``), a small body on slides along the
  ground that carries the ground's tangential spring, unless the export is
  asked for the bare link tree (``pads=False``, for comparing dynamics).
* The ground: the floor plane, each terrain feature (a step or box as a box
  geom, a slope as a tilted plane that replaces the floor), every surface
  ``CONTACT_RADIUS`` below legdsl's so that a contact sphere touches it
  exactly when the contact point reaches legdsl's surface. Each contact
  sphere meets each surface through an explicit ``<pair>`` whose
  ``solref``/``solimp``/``solreffriction`` carry the ``.leg`` ground's normal
  spring-damper (or paw pad) and, without pads, the tangent damper
  (``mjcontact.py``); the spheres collide with nothing else.
* Actuators: springs (eq. 1) and servos (eq. 5) are MuJoCo ``position``
  actuators with ``kp = k``, ``kv = b`` and ``forcerange = +-max``: their force
  ``kp (ctrl - q) - kv qd`` clipped to the range is legdsl's law exactly when
  ``ctrl`` holds the rest length or set point. ``force`` actuators are
  ``motor`` actuators (gear 1). The keyframe ``initial`` holds the model's
  initial state and the controls that reproduce the declared rest lengths and
  set points.
* No damping, armature or friction loss on the model's joints (the pads'
  slides have theirs); ``RK4`` at the creature's own step (its ``simulation`` block's ``dt``,
  which ``legdsl scale`` writes as 0.4 ms sqrt(L)), else the paper's 0.0004 s; gravity from
  the model. The contact spheres are 5 mm, or a fiftieth of the longest link of a creature
  whose links are all shorter than 25 cm (a 0.7 mm mite's toe is not a 5 mm ball), or of its
  size for a creature without link lengths.
* ``<statistic>`` (MuJoCo's view scale) and a step's length are the creature's (``mjsizes.py``).
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import numpy as np

from legdsl import __version__
from legdsl.export.mjcontact import (
    FRICTION_IMPRATIO,
    FRICTION_RATE,
    contact_parameters,
    stop_parameters,
)
from legdsl.export.mjpads import (
    MUJOCO_SMALLEST_INERTIA,
    AnchorPad,
    anchor_pads,
    carrier_inertials,
)
from legdsl.export.mjsizes import (
    contact_radius,
    creature_box,
    creature_size,
    step_half_length,
)
from legdsl.export.xml import fresh, num, nums, rgba, to_text
from legdsl.ir.model import Body, Joint, Model
from legdsl.lang.errors import Diagnostics, LegError

TIMESTEP = 0.0004  # s, the paper's integration step, for a creature without its own dt
# legdsl's default ground does not slip; MuJoCo needs a finite coefficient.
NO_SLIP_FRICTION = 10.0
FLOOR_RGBA = "0.85 0.85 0.8 1"
# The pads' level constraint: stiff (5 steps' time constant, critically damped) and hard
# (impedance 0.99 to 0.999), so that a pad springing back after liftoff, which its body's
# turning pushes sideways, stays within 0.1 degrees of level; it only turns the pad, whose
# inertia is tiny, so it pushes nothing else.
LEVEL_STEPS = 5.0  # time constants of LEVEL_SOLREF, in time steps
LEVEL_SOLIMP = (0.99, 0.999, 0.001, 0.5, 2.0)
# An anchor pad's friction for legdsl's no slip. legdsl's tangent spring holds however light
# the load; MuJoCo's pad slips past mu N, so mu is large (its friction rows are hard and the
# cone elliptic, so this costs nothing). At 10 a toe touching down lightly slipped.
PAD_NO_SLIP_FRICTION = 1000.0
# m: a level pad's rolling friction over its sliding friction. The torque asked of rolling
# friction is the normal force times the slide (plus the friction times the sphere's
# radius), so an arm well above the slides' travel never uses up the cone.
PAD_ROLLING_ARM = 1.0


def mujoco_timestep(model: Model) -> float:
    """The creature's own integration step, else the paper's: MuJoCo's explicit RK4 and the
    pads' rates (mjpads.py, mjcontact.py) are set for it, and a small creature's (0.4 ms sqrt(L)
    when ``legdsl scale`` wrote it) is shorter than its fastest spring's period asks."""
    return model.simulation.dt or TIMESTEP


def model_to_mjcf(model: Model, pads: bool = True, drawing: bool = False) -> str:
    """The MJCF text of ``model``; the same model gives the same bytes.

    ``pads``: hold each contact on an anchor pad (``mjpads.py``), which carries the ground's
    tangential spring; without them (for comparing dynamics) the tree is exactly the model's.
    ``drawing``: for MuJoCo's kinematics and renderer only (``legdsl replay``), so inertias
    below MuJoCo's floor are raised to it (the compiler's ``boundinertia``) and not refused.
    """
    if not drawing:
        _check_names(model)
    bodies, free_joint = mjcf_names(model)
    timestep, radius = mujoco_timestep(model), contact_radius(model)
    anchors = anchor_pads(model, timestep, radius) if pads else ()
    if not drawing:  # a body MuJoCo refuses as declared, before what its pads take from it
        _loadable_inertias(model, {b.name: (b.mass, b.com, b.inertia) for b in model.bodies})
    inertials = carrier_inertials(model, anchors)
    if not drawing:
        _loadable_inertias(model, inertials)
    root = ET.Element("mujoco", model=model.name)
    root.append(
        ET.Comment(
            f" Generated by legdsl {__version__} from {Path(model.span.file).name} "
            f"(creature '{model.name}'); do not edit. Bodies are written at zero joint "
            "coordinates; the keyframe 'initial' holds the declared initial state. "
        )
    )
    compiler = ET.SubElement(
        root, "compiler", angle="radian", inertiafromgeom="false", autolimits="true"
    )
    if drawing:
        compiler.set("boundinertia", num(MUJOCO_SMALLEST_INERTIA))
    # An elliptic friction cone: no slip (the paper's ground) is exported as a large friction
    # coefficient, and with MuJoCo's default pyramidal cone such a coefficient makes the contact
    # solve so soft that a creature sinks through the floor (seen in benchmarks/bench_runtime.py).
    option = ET.SubElement(
        root,
        "option",
        integrator="RK4",
        timestep=num(timestep),
        gravity=nums(model.gravity),
        cone="elliptic",
    )
    if anchors:  # hard friction: the pads stick (mjcontact.py)
        option.set("impratio", num(FRICTION_IMPRATIO))
    _defaults(root, model, radius)
    # MuJoCo's view scale (near clipping plane, the viewer's framing) is the creature's: its own
    # counts the terrain's boxes, and a 100 m step clipped a 5 cm hopper from every view
    low, high = creature_box(model)
    ET.SubElement(
        root, "statistic", extent=num(creature_size(model)), center=nums((low + high) / 2)
    )
    world = ET.SubElement(root, "worldbody")
    ET.SubElement(world, "light", name="sun", pos="0 0 4", dir="0 0 -1", directional="true")
    taken = {c.name for c in model.contacts}
    surfaces = _ground(world, model, taken, radius)

    children: dict[str | None, list[Body]] = {}
    for b in model.bodies:
        children.setdefault(b.parent, []).append(b)
    joints = {j.child: j for j in model.joints}
    on_pad = {pad.contact: pad for pad in anchors}
    stops = stop_parameters(model, anchors)
    qpos: list[float] = []  # the keyframe, in MuJoCo's order of joints
    qvel: list[float] = []

    def emit(parent: ET.Element, body: Body) -> None:
        joint = joints[body.name]
        qpos.extend(model.q0[joint.q_start : joint.q_start + joint.nq])
        qvel.extend(model.v0[joint.v_start : joint.v_start + joint.nv])
        el = ET.SubElement(parent, "body", name=bodies[body.name], pos=nums(joint.origin))
        _joint(el, joint, stops, free_joint)
        mass, com, i = inertials[body.name]
        ET.SubElement(
            el,
            "inertial",
            pos=nums(com),
            mass=num(mass),
            fullinertia=nums((i[0][0], i[1][1], i[2][2], i[0][1], i[0][2], i[1][2])),
        )
        _shape(el, body)
        for c in model.contacts:
            if c.body == body.name:
                pad = on_pad.get(c.name)
                if pad is None:
                    ET.SubElement(el, "geom", {"class": "contact"}, name=c.name, pos=nums(c.point))
                else:
                    _anchor_pad(el, pad)
                    joints_on_pad = len(pad.slides) + (pad.level is not None)
                    qpos.extend([0.0] * joints_on_pad)
                    qvel.extend([0.0] * joints_on_pad)
                ET.SubElement(el, "site", {"class": "contact"}, name=c.name, pos=nums(c.point))
        for child in children.get(body.name, []):
            emit(el, child)

    for b in children.get(None, []):
        emit(world, b)

    _contact_pairs(root, model, surfaces, anchors, timestep)
    _level_pads(root, anchors, timestep)
    _actuators(root, model)
    key = ET.SubElement(ET.SubElement(root, "keyframe"), "key", name="initial")
    key.set("qpos", nums(qpos))
    if qvel:
        key.set("qvel", nums(qvel))
    if model.actuators:
        key.set("ctrl", nums(_initial_ctrl(a.kind, dict(a.params)) for a in model.actuators))
    return to_text(root)


def _loadable_inertias(model: Model, inertials: dict[str, Any]) -> None:
    """A body whose inertia MuJoCo would refuse is an error here, saying why, rather than a
    file MuJoCo cannot load."""
    for body in model.bodies:
        smallest = float(np.linalg.eigvalsh(np.asarray(inertials[body.name][2])).min())
        if 0 < smallest < MUJOCO_SMALLEST_INERTIA:
            raise LegError.at(
                body.span,
                f"body '{body.name}' has a principal inertia of {smallest:.3g} kg*m^2, and MuJoCo "
                f"loads none below {MUJOCO_SMALLEST_INERTIA:g} (in SI units, which the MJCF "
                "export writes); export the creature scaled up (legdsl scale FILE --by 100: "
                "it moves the same, scaled by docs/scaling.md's rule)",
            )


def mjcf_names(model: Model) -> tuple[dict[str, str], str]:
    """The MJCF name of each body, and of the 3D free root's joint: the .leg's and 'root',
    except where MuJoCo reserves a body's ('world') or a coordinate is named 'root': then a
    fresh one (``world_``, ``root_``). ``legdsl export`` refuses those names (``_check_names``),
    so a file a person reads keeps the .leg's names; ``legdsl replay`` only draws, so it
    renames them rather than refuse the creature."""
    taken = {b.name for b in model.bodies} | {"world"}
    bodies = {b.name: fresh(b.name, taken) if b.name == "world" else b.name for b in model.bodies}
    return bodies, fresh("root", {d.name for d in model.dofs})


def _check_names(model: Model) -> None:
    """Names MuJoCo reserves or that legdsl's namespaces do not already keep apart, every one
    at once (told one at a time, each rename was one more round trip)."""
    diag = Diagnostics({})
    for b in model.bodies:
        if b.name == "world":
            diag.error(b.span, "MuJoCo reserves the body name 'world'; rename this body")
    if any(j.is_free_3d for j in model.joints):
        for j in model.joints:
            if not j.is_free_3d and any(d.name == "root" for d in j.dofs):
                diag.error(
                    j.span,
                    "in MJCF the free root's joint is called 'root'; rename this coordinate",
                )
    diag.raise_if_any()


def _defaults(root: ET.Element, model: Model, radius: float) -> None:
    d = ET.SubElement(root, "default")
    shape = ET.SubElement(d, "default", {"class": "shape"})
    # Drawing only: explicit inertials carry the mass, and shapes do not collide.
    ET.SubElement(shape, "geom", contype="0", conaffinity="0", mass="0", group="1")
    contact = ET.SubElement(d, "default", {"class": "contact"})
    ET.SubElement(
        contact,
        "geom",
        type="sphere",
        size=num(radius),
        mass="0",
        # they touch the ground through the explicit pairs in <contact> only
        contype="0",
        conaffinity="0",
        condim="3",
        friction=_friction(model),
        rgba="0.9 0.2 0.2 1",
        group="2",
    )
    ET.SubElement(contact, "site", type="sphere", size=num(radius), group="3")


def _friction(model: Model) -> str:
    mu = model.ground.friction if model.ground is not None else None
    return nums((NO_SLIP_FRICTION if mu is None else mu, 0.005, 0.0001))


def _anchor_pad(body: ET.Element, pad: AnchorPad) -> None:
    """The pad at the contact point on its tangent slides, carrying the contact sphere."""
    el = ET.SubElement(body, "body", name=pad.name, pos=nums(pad.point))
    if pad.level is not None:
        ET.SubElement(el, "joint", name=pad.level, type="hinge", axis="0 1 0")
    for name, axis in pad.slides:
        ET.SubElement(
            el,
            "joint",
            name=name,
            type="slide",
            axis=nums(axis),
            stiffness=num(pad.k),
            damping=num(pad.b),
            armature=num(pad.mass),
        )
    ET.SubElement(
        el, "inertial", pos="0 0 0", mass=num(pad.mass), diaginertia=nums([pad.inertia] * 3)
    )
    ET.SubElement(el, "geom", {"class": "contact"}, name=pad.contact)


def _level_pads(root: ET.Element, pads: tuple[AnchorPad, ...], timestep: float) -> None:
    """A planar creature's pads kept level: each pad's hinge plus its body's hinges (a fixed
    tendon) held at the initial pose's sum, so the pad keeps its initial world orientation."""
    level = [pad for pad in pads if pad.level is not None]
    if not level:
        return
    tendons = ET.SubElement(root, "tendon")
    equality = ET.SubElement(root, "equality")
    for pad in level:
        assert pad.level is not None
        fixed = ET.SubElement(tendons, "fixed", name=pad.level)
        for joint, coef in (*pad.turns, (pad.level, 1.0)):
            ET.SubElement(fixed, "joint", joint=joint, coef=num(coef))
        # MuJoCo holds tendon1 - (its length at qpos0, here 0) = polycoef[0]
        ET.SubElement(
            equality,
            "tendon",
            name=pad.level,
            tendon1=pad.level,
            polycoef=nums((pad.turned, 0.0, 0.0, 0.0, 0.0)),
            solref=nums((LEVEL_STEPS * timestep, 1.0)),
            solimp=nums(LEVEL_SOLIMP),
        )


def _contact_pairs(
    root: ET.Element,
    model: Model,
    surfaces: list[str],
    pads: tuple[AnchorPad, ...],
    timestep: float,
) -> None:
    """Each contact sphere against each ground surface, with the ground's law (mjcontact.py);
    the pads' friction rate is RK4's margin at the step (FRICTION_RATE at the paper's)."""
    solver = contact_parameters(model, pads, FRICTION_RATE * (TIMESTEP / timestep))
    if not solver or not surfaces:
        return
    pairs = ET.SubElement(root, "contact")
    slide, spin, roll = _friction(model).split()
    level = {pad.contact for pad in pads if pad.level is not None}
    if pads:
        assert model.ground is not None
        mu = model.ground.friction
        slide = num(PAD_NO_SLIP_FRICTION if mu is None else mu)
    for c in model.contacts:
        # A level pad turns freely about y, so the ground holds its turn (rolling friction):
        # the normal force then reaches the body at the contact point, as in legdsl, and not
        # at the anchor with the moment N * slide. The rolling coefficient is the sliding one
        # times PAD_ROLLING_ARM: MuJoCo's regulariser of a friction row scales with the
        # inverse square of its coefficient, so the two are as hard as each other.
        rolling = num(float(slide) * PAD_ROLLING_ARM) if c.name in level else roll
        for surface in surfaces:
            attrs = {
                "geom1": c.name,
                "geom2": surface,
                "condim": "6" if c.name in level else "3",
                "friction": " ".join((slide, slide, spin, rolling, rolling)),
                **solver[c.name],
            }
            ET.SubElement(pairs, "pair", attrs)


def _ground(world: ET.Element, model: Model, taken: set[str], r: float) -> list[str]:
    """The floor and the terrain, every surface ``r`` (the contact spheres') below legdsl's.

    A contact sphere then touches a surface exactly when its centre, the
    legdsl contact point, reaches legdsl's surface, in any orientation.
    """
    terrain = model.ground.terrain if model.ground is not None else ()
    slope = next((t for t in terrain if t.kind == "slope"), None)
    if slope is not None:  # the whole ground, tilted about y and rising towards +x
        a = slope.get("angle")
        normal = (-math.sin(a), 0.0, math.cos(a))
        ET.SubElement(
            world,
            "geom",
            name=(name := fresh("slope", taken)),
            type="plane",
            size="0 0 0.05",
            pos=nums(-r * n for n in normal),
            # a turn of -angle about y takes +z onto the slope's normal
            quat=nums((math.cos(-a / 2), 0.0, math.sin(-a / 2), 0.0)),
            rgba=FLOOR_RGBA,
            friction=_friction(model),
        )
        return [name]
    ET.SubElement(
        world,
        "geom",
        name=(floor_name := fresh("floor", taken)),
        type="plane",
        size="0 0 0.05",
        pos=nums((0.0, 0.0, -r)),
        rgba=FLOOR_RGBA,
        friction=_friction(model),
    )
    names = [floor_name]
    for i, t in enumerate(terrain):
        h = t.get("height")
        if h <= 0:  # legdsl's ground is the highest feature or the floor
            world.append(
                ET.Comment(
                    f" terrain {i} ({t.kind}, height {num(h)} m) is below the floor: omitted "
                )
            )
            continue
        if t.kind == "step":
            half = step_half_length(model)
            lo, hi = (t.get("x"), t.get("x") + 2 * half), (-half, half)
        else:
            lo, hi = (t.get("x0"), t.get("x1")), (t.get("y0"), t.get("y1"))
        ET.SubElement(
            world,
            "geom",
            name=(box := fresh(f"terrain{i}", taken)),
            type="box",
            pos=nums(((lo[0] + lo[1]) / 2, (hi[0] + hi[1]) / 2, h / 2 - r)),
            size=nums(((lo[1] - lo[0]) / 2, (hi[1] - hi[0]) / 2, h / 2)),
            rgba="0.7 0.7 0.65 1",
            friction=_friction(model),
        )
        names.append(box)
    return names


def _joint(body: ET.Element, joint: Joint, stops: dict[str, dict[str, str]], free: str) -> None:
    if joint.is_free_3d:
        ET.SubElement(body, "freejoint", name=free)
        return
    for d in joint.dofs:  # in order: MuJoCo composes a body's joints as a chain
        el = ET.SubElement(body, "joint", name=d.name, type=d.motion, axis=nums(d.axis))
        if d.limits is not None:
            el.set("range", nums(d.limits))
            if d.name not in stops:  # legdsl's limits alone are no force: nor are MuJoCo's
                el.set("limited", "false")
        for key, value in stops.get(d.name, {}).items():  # the stop's spring-damper
            el.set(key, value)


def _shape(body: ET.Element, b: Body) -> None:
    s = b.shape
    attrs = {"class": "shape", "rgba": rgba(b.color)}
    if s.kind in ("capsule", "cylinder", "frustum") and b.length:
        r = (s.get("r0") + s.get("r1")) / 2 if s.kind == "frustum" else s.get("r")
        kind = "cylinder" if s.kind == "cylinder" else "capsule"
        ET.SubElement(
            body, "geom", attrs, type=kind, size=num(r), fromto=nums((0.0, 0.0, 0.0, *b.tip))
        )
    elif s.kind == "box":
        half = (s.get("x") / 2, s.get("y") / 2, s.get("z") / 2)
        ET.SubElement(body, "geom", attrs, type="box", size=nums(half), pos=nums(s.center))
    else:  # a sphere, or a link shape on a body without a length
        r = s.get("r") if s.kind != "frustum" else max(s.get("r0"), s.get("r1"))
        ET.SubElement(body, "geom", attrs, type="sphere", size=num(r), pos=nums(s.center))


def _actuators(root: ET.Element, model: Model) -> None:
    if not model.actuators:
        return
    acts = ET.SubElement(root, "actuator")
    for a in model.actuators:
        p = dict(a.params)
        if a.kind in ("spring", "servo"):
            kp, kv = (p["k"], p["b"]) if a.kind == "spring" else (p["kp"], p["kv"])
            el = ET.SubElement(acts, "position", name=a.name, joint=a.dof, kp=num(kp), kv=num(kv))
        else:
            el = ET.SubElement(acts, "motor", name=a.name, joint=a.dof, gear="1")
        if a.max is not None:
            el.set("forcerange", nums((-a.max, a.max)))


def _initial_ctrl(kind: str, params: dict[str, float]) -> float:
    """The control that makes a MuJoCo actuator apply the declared law at rest."""
    if kind == "spring":
        return params["rest"]
    if kind == "servo":
        return params["setpoint"]
    return params.get("value", 0.0)
