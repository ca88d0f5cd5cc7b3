"""The checked model IR: what a creature *is*, in SI units, with names resolved.

Frames and conventions (also in docs/language.md):

* World: z up, x forward, y to the left. A planar creature moves in the x-z
  plane and turns about y (positive pitch turns +x towards -z, the right-hand
  rule about +y).
* Every body has a frame whose origin is its joint's location and whose axes
  are parallel to its parent's when all joint coordinates are zero. A body's
  mass centre, contact points, child joint locations and drawing shape are
  given in this frame.
* A joint is a chain of one-degree-of-freedom primitives (``Dof``): a slide
  along, or a hinge about, a unit axis of the joint frame, applied in order.
  Revolute and prismatic joints have one; gimbal two; ball three; a planar
  free root three (x, z, pitch). The only exception is the 3D free root,
  which has seven position coordinates and six velocities:

      q = (x, y, z, qw, qx, qy, qz)   position of the body frame in the world,
                                      and its orientation as a unit quaternion
      v = (vx, vy, vz, wx, wy, wz)    linear velocity of the body frame origin
                                      in world axes; angular velocity in body axes

  which is MuJoCo's convention for a free joint.
* Coordinates are ordered root first, then joints in tree order (a parent's
  joint before its children's, siblings in the order they were written), and
  each joint's primitives in axis order.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from legdsl.ir.controller import Controller
from legdsl.ir.scene import Scene
from legdsl.lang.errors import Span

# The coordinates and speeds of a 3D free root, in q and v (names no joint may take)
FREE_3D_Q_NAMES = ("x", "y", "z", "qw", "qx", "qy", "qz")
FREE_3D_V_NAMES = ("vx", "vy", "vz", "wx", "wy", "wz")

Vec3 = tuple[float, float, float]
Mat3 = tuple[Vec3, Vec3, Vec3]


@dataclass(frozen=True)
class Shape:
    """A drawing shape in the body frame. ``kind`` is box, frustum, capsule, sphere or cylinder.

    box: size (x, y, z) centred at ``center``; frustum/capsule/cylinder: radii along the
    link from the joint to ``length * direction``; sphere: radius at ``center``.
    """

    kind: str
    params: tuple[tuple[str, float], ...]
    center: Vec3 = (0.0, 0.0, 0.0)

    def get(self, key: str) -> float:
        return dict(self.params)[key]


@dataclass(frozen=True)
class Body:
    name: str
    parent: str | None
    joint: str
    mass: float
    com: Vec3
    inertia: Mat3  # about the mass centre, in body axes
    length: float | None
    direction: Vec3  # unit vector along the link, in the body frame
    shape: Shape
    color: str | None
    span: Span

    @property
    def tip(self) -> Vec3:
        """The distal end of the link: ``length * direction`` (the origin if no length)."""
        length = self.length or 0.0
        return (
            length * self.direction[0],
            length * self.direction[1],
            length * self.direction[2],
        )


@dataclass(frozen=True)
class Dof:
    """One degree of freedom: a slide or hinge about ``axis`` (unit, joint frame)."""

    name: str
    joint: str
    motion: str  # "slide" or "hinge"
    axis: Vec3
    q_index: int
    v_index: int
    initial: float
    initial_rate: float
    limits: tuple[float, float] | None


@dataclass(frozen=True)
class Joint:
    name: str
    kind: str  # free, fixed (root welded to the world), revolute, prismatic, gimbal, ball, weld
    parent: str | None  # parent body, None for the root
    child: str
    origin: Vec3  # location in the parent frame (the world for the root)
    dofs: tuple[Dof, ...]
    q_start: int
    nq: int
    v_start: int
    nv: int
    span: Span

    @property
    def is_free_3d(self) -> bool:
        return self.kind == "free" and self.nq == 7


def axes_spread(axes: tuple[Vec3, ...] | list[Vec3], angles: list[float]) -> float:
    """How far three hinges applied in order, at these angles, are from gimbal lock: the
    volume their turned axes span, 1 at right angles, 0 when they lie in one plane (the
    joint's mass matrix is then singular and its rates grow without bound near there)."""

    def turn(k: Vec3, angle: float, v: Vec3) -> Vec3:  # Rodrigues
        c, s = math.cos(angle), math.sin(angle)
        dot = sum(p * q for p, q in zip(k, v, strict=True))
        cross = (k[1] * v[2] - k[2] * v[1], k[2] * v[0] - k[0] * v[2], k[0] * v[1] - k[1] * v[0])
        return (
            v[0] * c + cross[0] * s + k[0] * dot * (1 - c),
            v[1] * c + cross[1] * s + k[1] * dot * (1 - c),
            v[2] * c + cross[2] * s + k[2] * dot * (1 - c),
        )

    a1, a2, a3 = axes
    w1, w2, w3 = a1, turn(a1, angles[0], a2), turn(a1, angles[0], turn(a2, angles[1], a3))
    return abs(
        w1[0] * (w2[1] * w3[2] - w2[2] * w3[1])
        - w1[1] * (w2[0] * w3[2] - w2[2] * w3[0])
        + w1[2] * (w2[0] * w3[1] - w2[1] * w3[0])
    )


@dataclass(frozen=True)
class Actuator:
    """A force on one coordinate. ``kind``: spring (eq. 1), servo (eq. 5) or force.

    The generalized force is ``-(k (q - rest) + b qd)`` for a spring and
    ``-kp (q - setpoint) - kv qd`` for a servo, clipped to ``[-max, max]``
    when ``max`` is set; for ``force`` it is the commanded value.
    """

    name: str
    kind: str
    dof: str
    params: tuple[tuple[str, float], ...]
    max: float | None
    rotary: bool
    span: Span

    def get(self, key: str) -> float:
        return dict(self.params)[key]


# Which settings a controller may change, per kind (the rest are read-only).
SETTABLE = {
    "spring": ("k", "b", "rest"),
    "servo": ("kp", "kv", "setpoint"),
    "force": ("force",),
}

# Actuator arguments that must not be negative, in the .leg file and through --set alike.
NON_NEGATIVE = ("k", "b", "kp", "kv", "max")


def setting_kind(key: str, rotary: bool) -> str:
    """The physical kind (a key of ``units.KINDS``) of an actuator setting on a rotary or sliding joint."""
    linear, angular = {
        "k": ("linear stiffness", "angular stiffness"),
        "kp": ("linear stiffness", "angular stiffness"),
        "b": ("linear damping", "angular damping"),
        "kv": ("linear damping", "angular damping"),
        "rest": ("length", "angle"),
        "setpoint": ("length", "angle"),
        "force": ("force", "torque"),
        "max": ("force", "torque"),
    }[key]
    return angular if rotary else linear


@dataclass(frozen=True)
class Contact:
    name: str
    body: str
    point: Vec3  # in the body frame
    span: Span


@dataclass(frozen=True)
class SpringDamper:
    k: float
    b: float


@dataclass(frozen=True)
class Pad:
    """The paw pad of eq. (6): ``f = k (thickness / (thickness + z) - 1)`` for ``z < 0``, plus damping."""

    k: float
    thickness: float
    b: float


@dataclass(frozen=True)
class Terrain:
    """A raised feature. step: floor at ``height`` for x >= ``x``; box: an axis-aligned block."""

    kind: str
    params: tuple[tuple[str, float], ...]
    span: Span

    def get(self, key: str) -> float:
        return dict(self.params)[key]


@dataclass(frozen=True)
class Ground:
    normal: SpringDamper | Pad  # the vertical spring: linear, or the paw pad of eq. (6)
    tangent: SpringDamper
    torsion: SpringDamper | None
    friction: float | None  # None: no slip (the paper's assumption)
    terrain: tuple[Terrain, ...]
    span: Span


@dataclass(frozen=True)
class SimulationDefaults:
    """``simulation { dt 0.4 ms  control_dt 2 ms  record_rate 200 Hz }``: the creature's own
    defaults for ``legdsl run`` (its --dt, --control-dt, --record-rate override them); a
    dynamically scaled file carries its scaled ones. In SI units; None: the runner's default."""

    dt: float | None = None
    control_dt: float | None = None
    record_rate: float | None = None


@dataclass(frozen=True)
class Leg:
    name: str
    joints: tuple[str, ...]  # from the hip outwards; the first joint's origin is the hip point
    foot: str  # a contact: the leg's foot point (placed, measured for length and clearance)
    aliases: tuple[tuple[str, str], ...]  # leg-local names for actuators, joints, coordinates
    span: Span
    # ``foot sole, heel, toe``: the contacts after the first; left out of a fingerprint when
    # empty, so that a one-footed leg's generated modules stay as they were
    more_soles: tuple[str, ...] = field(default=(), metadata={"omit_empty": True})

    @property
    def soles(self) -> tuple[str, ...]:
        """Every contact the leg stands on: it touches the ground while any of them does."""
        return (self.foot, *self.more_soles)


@dataclass(frozen=True)
class Hip:
    """A leg's hip point: the origin of body ``body``, or where ``at`` (in that body's frame)
    puts it. The runtime's sensors, recorder and foot placer in Python and in C read it alike."""

    body: int
    at: Vec3 | None = None

    def point(self, poses: Any) -> tuple[float, float, float]:
        """In the world, from ``body_poses``: (origin, row-major rotation) per body."""
        pos, r = poses[self.body]
        if self.at is None:
            return pos  # the body's origin, as it is (a turning first joint)
        a = self._turned(r)
        return (pos[0] + a[0], pos[1] + a[1], pos[2] + a[2])

    def velocity(self, poses: Any, velocities: Any) -> tuple[float, float, float]:
        """In the world, from ``body_velocities``: (origin's velocity, angular velocity)."""
        vel, w = velocities[self.body]
        if self.at is None:
            return vel
        a = self._turned(poses[self.body][1])
        return (
            vel[0] + (w[1] * a[2] - w[2] * a[1]),
            vel[1] + (w[2] * a[0] - w[0] * a[2]),
            vel[2] + (w[0] * a[1] - w[1] * a[0]),
        )

    def _turned(self, r: Any) -> tuple[float, float, float]:
        """``at`` turned into the world by the body's rotation ``r`` (row-major)."""
        assert self.at is not None
        x, y, z = self.at
        return (r[0] * x + r[1] * y + r[2] * z, r[3] * x + r[4] * y + r[5] * z,
                r[6] * x + r[7] * y + r[8] * z)  # fmt: skip


@dataclass(frozen=True)
class Stop:
    """A joint limit as a mechanical stop: past ``low`` or ``high`` the coordinate meets a
    one-sided spring-damper (``k`` N/m or N*m/rad, ``b`` N*s/m or N*m*s/rad) pushing it back.
    Kept beside the joints, not in them: stops are runtime forces, not part of the dynamics
    (the generated modules and their fingerprints do not depend on them)."""

    dof: str
    q_index: int
    v_index: int
    low: float
    high: float
    k: float
    b: float
    span: Span
    units: tuple[str, str]  # k's and b's as written on its line (messages give them so)


@dataclass(frozen=True)
class Model:
    name: str
    source: str
    planar: bool
    gravity: Vec3
    bodies: tuple[Body, ...]  # tree order: every parent before its children
    joints: tuple[Joint, ...]  # joints[i] carries bodies[i]
    actuators: tuple[Actuator, ...]
    contacts: tuple[Contact, ...]
    ground: Ground | None
    legs: tuple[Leg, ...]
    controllers: tuple[Controller, ...]
    q0: tuple[float, ...]
    v0: tuple[float, ...]
    span: Span
    simulation: SimulationDefaults = SimulationDefaults()
    stops: tuple[Stop, ...] = ()  # joint limits written with 'stop k = ..., b = ...'
    scenes: tuple[Scene, ...] = ()  # runs written in the file (scene NAME { ... })

    @property
    def dofs(self) -> tuple[Dof, ...]:
        return tuple(d for j in self.joints for d in j.dofs)

    @property
    def nq(self) -> int:
        return sum(j.nq for j in self.joints)

    @property
    def nv(self) -> int:
        return sum(j.nv for j in self.joints)

    @property
    def q_names(self) -> tuple[str, ...]:
        names: list[str] = []
        for j in self.joints:
            names += FREE_3D_Q_NAMES if j.is_free_3d else [d.name for d in j.dofs]
        return tuple(names)

    @property
    def v_names(self) -> tuple[str, ...]:
        names: list[str] = []
        for j in self.joints:
            names += FREE_3D_V_NAMES if j.is_free_3d else [d.name for d in j.dofs]
        return tuple(names)

    @property
    def v_angular(self) -> tuple[bool, ...]:
        """Whether each entry of v is a rate of turn (rad/s), else a speed (m/s)."""
        angular: list[bool] = []
        for j in self.joints:
            free = (False,) * 3 + (True,) * 3
            angular += free if j.is_free_3d else [d.motion == "hinge" for d in j.dofs]
        return tuple(angular)

    @property
    def welded_root(self) -> str | None:
        """The root body's name when it is welded to the world (``fixed at``): it goes
        nowhere, and has no height to fall from or attitude to measure; else None."""
        root = next((j for j in self.joints if j.parent is None), None)
        return root.child if root is not None and root.kind == "fixed" else None

    @property
    def total_mass(self) -> float:
        return sum(b.mass for b in self.bodies)

    def body(self, name: str) -> Body:
        return next(b for b in self.bodies if b.name == name)

    def joint(self, name: str) -> Joint:
        return next(j for j in self.joints if j.name == name)

    def leg_hip(self, leg: Leg) -> Hip:
        """Where the leg's first joint sits on the body it hangs from. A joint that turns
        keeps the origin of the body it moves there; a slide carries that origin along, so its
        hip point is the joint's place on its parent (else the leg's length would not change)."""
        joint = self.joint(leg.joints[0])
        child = next(i for i, b in enumerate(self.bodies) if b.joint == joint.name)
        if joint.kind != "prismatic" or joint.parent is None:
            return Hip(child)
        return Hip(
            next(i for i, b in enumerate(self.bodies) if b.name == joint.parent), joint.origin
        )

    def scene(self, name: str) -> Scene:
        return next(s for s in self.scenes if s.name == name)

    def controller(self, name: str) -> Controller:
        return next(c for c in self.controllers if c.name == name)
