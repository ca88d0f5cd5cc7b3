"""Anchor pads: the ``.leg`` ground's tangential spring in the MJCF export.

legdsl holds a touching foot tangentially with a spring-damper pulling it
towards an anchor set where it touched down (``sim/contact.py``). MuJoCo's
friction rows have no position error, so they can carry the damper but not
the spring. The export therefore gives every contact an *anchor pad*: a small
body, child of the contact's body at the contact point, on slide joints along
the ground's tangents (one for a planar creature, two in 3D) whose
``stiffness`` and ``damping`` are the ``.leg`` ``tangent spring(k, b)``. The
contact sphere sits on the pad and its friction is hard (``mjcf.py`` sets a
large ``impratio``), so the pad sticks where it touched down while the body
moves against the joint's spring-damper: the pad is the anchor. In flight the
spring returns the pad to the contact point, which resets the anchor for the
next touchdown. A finite friction coefficient lets the pad slip at ``mu N``,
as legdsl's anchor follows a foot pulling harder than ``mu N``.

The slides' axes are the ground's tangents with the body turned as in the
declared initial pose. In a planar creature the pad first turns about y on a
hinge of its own, which a tendon equality holds at minus the body's turn from
that pose (the turn is the signed sum of the hinge angles from the root), so
the slide stays on the ground's tangent however the foot lands. In 3D a body's
turn is not a linear function of the coordinates, so the slides turn with the
body: a foot that touches down turned by an angle ``a`` from its initial pose
has its slides ``a`` off the ground, and the normal force's share ``N tan a``
then loads them too. The torsion spring (3D) is not exported.

The pad's mass is taken out of its body (mass, mass centre and inertia), so
at rest the body with its pads has the declared mass properties exactly (a planar
body: its moment about y, the only one that acts; its other moments are chosen to keep
it a rigid body); how heavy it is follows from the integrator's stability
(PAD_STEP_EIGENVALUE).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from legdsl.export.motion import quaternion_to_matrix
from legdsl.export.xml import fresh
from legdsl.ir.model import Dof, Model, Vec3
from legdsl.lang.errors import Diagnostic, InternalError, LegError

# The pad's slide is a mass on a spring-damper integrated explicitly (RK4, MuJoCo's passive
# forces included): its fastest eigenvalue is at most b / m (overdamped) or sqrt(k / m)
# (underdamped), m being the slide's inertia. RK4 is stable for |lambda dt| up to 2.78 on the
# real axis and 2.83 on the imaginary one. The slide's armature alone is made large enough
# for |lambda dt| <= PAD_STEP_EIGENVALUE; the pad's mass adds to it as far as the body it
# hangs from lets it move, which halves |lambda dt| under a heavy body. The pad's mass equals
# its armature: while the pad sticks, the slide moves at minus the body's tangential
# velocity, and the armature's kinetic energy then makes up exactly the pad's tangential
# share, so that in stance the body moves as if the pad were part of it (it is, at rest: its
# mass is the body's).
PAD_STEP_EIGENVALUE = 2.0


@dataclass(frozen=True)
class AnchorPad:
    contact: str
    body: str  # the contact's body, the pad's parent
    name: str  # the pad body's name
    point: Vec3  # the contact point, the pad's origin, in the parent's frame
    slides: tuple[tuple[str, Vec3], ...]  # joint name and unit axis in the parent's frame
    # planar creatures: a hinge (about y) before the slides, held by a tendon equality at
    # -(the body's turn from its initial pose), keeps the slide on the ground's tangent
    level: str | None
    turns: tuple[tuple[str, float], ...]  # the hinges that turn the body, with their signs
    turned: float  # sum of coef * q over ``turns`` in the initial pose
    k: float  # the tangent spring, N/m
    b: float  # and its damper, N*s/m
    mass: float  # also each slide's armature
    radius: float  # the contact sphere's, on the pad
    inertia: float  # about each axis through the pad's origin (a solid sphere, or MuJoCo's least)


# kg m^2: MuJoCo refuses a fullinertia with a smaller eigenvalue ("inertia must have positive
# eigenvalues"; measured with MuJoCo 3: 1e-14 loads, 3e-15 does not). MuJoCo has no units: in
# SI a creature of a few millimetres (a 0.7 mm mite's bodies: 1e-17 kg m^2) is below it.
MUJOCO_SMALLEST_INERTIA = 1e-14


def pad_mass(k: float, b: float, timestep: float) -> float:
    """The pad's mass and its slides' armature: see PAD_STEP_EIGENVALUE."""
    return max(b * timestep / PAD_STEP_EIGENVALUE, k * (timestep / PAD_STEP_EIGENVALUE) ** 2)


def anchor_pads(model: Model, timestep: float, radius: float) -> tuple[AnchorPad, ...]:
    """One pad per contact (none without a ground or with a zero tangent spring-damper)."""
    ground = model.ground
    if ground is None or (ground.tangent.k == 0.0 and ground.tangent.b == 0.0):
        return ()
    slope = next((t for t in ground.terrain if t.kind == "slope"), None)
    a = slope.get("angle") if slope is not None else 0.0
    normal = np.array([-math.sin(a), 0.0, math.cos(a)])  # the surface's, as in sim/contact.py
    t1 = np.array([normal[2], 0.0, -normal[0]])  # legdsl's first tangent, in the x-z plane
    tangents = [t1] if model.planar else [t1, np.cross(normal, t1)]
    rotation = initial_rotations(model)
    bodies = {b.name for b in model.bodies}
    joints = {d.name for d in model.dofs} | {"root"}
    turns = _planar_turns(model) if model.planar else {}
    mass = pad_mass(ground.tangent.k, ground.tangent.b, timestep)
    pads = []
    for c in model.contacts:
        name = fresh(f"{c.name}_pad", bodies)
        slides = []
        for i, t in enumerate(tangents):
            axis = rotation[c.body].T @ t  # the tangent in the body's frame
            joint = fresh(f"{c.name}_slide{'xy'[i]}", joints)
            slides.append((joint, (float(axis[0]), float(axis[1]), float(axis[2]))))
        level = fresh(f"{c.name}_level", joints) if model.planar else None
        hinges = turns.get(c.body, ())
        pads.append(
            AnchorPad(
                contact=c.name,
                body=c.body,
                name=name,
                point=c.point,
                slides=tuple(slides),
                level=level,
                turns=tuple((d.name, sign) for d, sign in hinges),
                turned=sum(sign * model.q0[d.q_index] for d, sign in hinges),
                k=ground.tangent.k,
                b=ground.tangent.b,
                mass=mass,
                radius=radius,
                # a solid sphere's, or MuJoCo's least (a 1 cm hopper's pad: 6e-16, refused)
                inertia=max(0.4 * mass * radius**2, MUJOCO_SMALLEST_INERTIA),
            )
        )
    return tuple(pads)


def _planar_turns(model: Model) -> dict[str, list[tuple[Dof, float]]]:
    """Per body of a planar creature, the hinges from the root to it, each with its axis's
    sign along y: the body's pitch in the world is the signed sum of their angles."""
    out: dict[str, list[tuple[Dof, float]]] = {}
    for body, joint in zip(model.bodies, model.joints, strict=True):
        chain = [] if joint.parent is None else list(out[joint.parent])
        for d in joint.dofs:
            if d.motion == "hinge":
                if abs(abs(d.axis[1]) - 1.0) > 1e-12:
                    raise InternalError(f"planar hinge {d.name} is not about y: {d.axis}")
                chain.append((d, d.axis[1]))
        out[body.name] = chain
    return out


def initial_rotations(model: Model) -> dict[str, np.ndarray]:
    """Each body's world rotation in the declared initial pose (legdsl's frame rule)."""
    out: dict[str, np.ndarray] = {}
    for body, joint in zip(model.bodies, model.joints, strict=True):
        r = np.eye(3) if joint.parent is None else out[joint.parent]
        if joint.is_free_3d:
            w, x, y, z = model.q0[joint.q_start + 3 : joint.q_start + 7]
            r = quaternion_to_matrix(np.array([x, y, z, w]))
        for d in joint.dofs:
            if d.motion == "hinge":
                r = r @ _turn(np.asarray(d.axis, float), model.q0[d.q_index])
        out[body.name] = r
    return out


def _turn(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rotation by ``angle`` about unit ``axis`` (Rodrigues)."""
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * k @ k


def _shift(mass: float, d: np.ndarray) -> np.ndarray:
    """Parallel axis term: a point mass ``mass`` at ``d`` from the reference point."""
    return mass * (float(d @ d) * np.eye(3) - np.outer(d, d))


def _rigid(inertia: np.ndarray) -> bool:
    """Whether an inertia tensor is a rigid body's: positive moments, triangle inequality."""
    moments = np.linalg.eigvalsh(inertia)
    return bool(moments.min() > 0 and 2 * moments.max() <= moments.sum() * (1 + 1e-9))


def carrier_inertials(
    model: Model, pads: tuple[AnchorPad, ...]
) -> dict[str, tuple[float, np.ndarray, np.ndarray]]:
    """Every body's (mass, mass centre, inertia about it) with its pads' mass taken out.

    The body and its pads at rest (zero slides) have the declared mass, mass
    centre and inertia (a planar body: its moment about y); a ``LegError`` at the
    contact says so if what is left is not a valid rigid body. A body welded to the world
    gives nothing: it never moves, and a 10 g test stand's frame was refused as too light.
    """
    out = {
        b.name: (b.mass, np.asarray(b.com, float), np.asarray(b.inertia, float))
        for b in model.bodies
    }
    refused: list[Diagnostic] = []  # every pad that cannot be carried, each told at its contact
    static = _welded_to_world(model)
    for pad in pads:
        if pad.body in static:  # MuJoCo never moves it: its mass is no one's, the pad's its own
            continue
        rest, centre, left = _taken_out(model.planar, out[pad.body], pad, pad.inertia)
        if left is None:
            contact = next(x for x in model.contacts if x.name == pad.contact)
            own = 0.4 * pad.mass * pad.radius**2  # a solid sphere's, before MuJoCo's floor
            floor = own < pad.inertia and (
                _taken_out(model.planar, out[pad.body], pad, own)[2] is not None
            )
            refused.append(
                Diagnostic(contact.span, _refusal(pad, own, floor) + contact.span.within)
            )
            continue
        out[pad.body] = (rest, centre, left)
    if refused:
        raise LegError(refused, {})
    return out


def _welded_to_world(model: Model) -> set[str]:
    """The bodies welded to the world: a fixed root and what is welded to it."""
    static: set[str] = set()
    for body, joint in zip(model.bodies, model.joints, strict=True):
        if joint.kind == "fixed" or (joint.kind == "weld" and joint.parent in static):
            static.add(body.name)
    return static


def _taken_out(
    planar: bool,
    inertial: tuple[float, np.ndarray, np.ndarray],
    pad: AnchorPad,
    pad_inertia: float,
) -> tuple[float, np.ndarray, np.ndarray | None]:
    """The body's (mass, mass centre, inertia) with the pad taken out; the inertia is None
    where what is left is not a rigid body's."""
    m, c, inertia = inertial
    p = np.asarray(pad.point, float)
    rest = m - pad.mass
    centre = (m * c - pad.mass * p) / rest if rest > 0 else c
    left = inertia - pad_inertia * np.eye(3) - _shift(pad.mass, p - c) - _shift(rest, centre - c)
    if planar and rest > 0 and left[1, 1] > 0 and not _rigid(left):
        # A planar creature turns about y only: its bodies' other moments (the checker
        # makes them Iyy) never act, so they are chosen to keep the carrier a rigid body.
        left = left[1, 1] * np.eye(3)
    return rest, centre, (left if rest > 0 and _rigid(left) else None)


def _refusal(pad: AnchorPad, own: float, floor: bool) -> str:
    """Why the pad's body cannot carry it: MuJoCo's inertia floor, which the pad's inertia
    (``own``) is raised to, where ``floor`` says the own one would fit (a 1 cm creature),
    else its mass."""
    start = f"the MJCF export's anchor pad for contact '{pad.contact}'"
    if floor:
        return (
            f"{start} has an inertia of {own:.3g} kg*m^2, below the least MuJoCo loads "
            f"({MUJOCO_SMALLEST_INERTIA:g}, in SI units, which the MJCF export writes), and body "
            f"'{pad.body}' cannot give the pad that least inertia: export the creature scaled up "
            "(legdsl scale FILE --by 100: it moves the same, scaled by docs/scaling.md's rule), "
            "or export with --no-anchor-pads"
        )
    return (
        f"{start} needs {pad.mass:.3g} kg (for its tangent spring-damper at MuJoCo's time step) "
        f"and body '{pad.body}' cannot give it: what is left of its mass and inertia is not a "
        "rigid body. Make the body heavier or its inertia larger, or export with --no-anchor-pads"
    )
