"""The mirror of an instance (``instance fr = leg(...) mirror sagittal``), on the checked model.

With ``M`` the reflection (``diag(1, -1, 1)`` sagittal, ``diag(-1, 1, 1)`` frontal), every
point and direction the instance declares becomes ``M p`` (joint locations, mass
centres, link directions, shape centres, contact points) and every inertia ``M I M``.
A hinge about ``a`` becomes a hinge about ``-M a`` (a reflection turns rotations the
other way) and a slide along ``d`` one along ``M d``. Where that axis is exactly the
opposite of the original, the axis is kept and the coordinate negated instead (its
initial value and rate, its limits and their stop ``[lo, hi] -> [-hi, -lo]``, and the rest
or setpoint of the instance's springs and servos on it), which is how a mirror is written by
hand:
the right hip's roll is about +x like the left's, with its angle's sign flipped.
Reflections keep lengths and angles, so a valid part stays valid. A body or contact
outside the instance that is placed ``at tip`` of one of its bodies is at the mirrored
tip; one placed at a point is where it is written, in the mirrored body's frame. A part of
the instance placed ``at tip`` of a body outside it is at that body's tip, mirrored (once)
only by the instance that holds that body.
"""

from __future__ import annotations

from dataclasses import replace

from legdsl.check.templates import MirrorPart
from legdsl.ir.model import Actuator, Body, Contact, Dof, Joint, Mat3, Stop, Vec3


def _neg(x: float) -> float:
    return 0.0 - x  # never -0.0, which would print (and hash) differently from 0.0


class Mirror:
    """One reflection, applied to what one mirrored instance declared."""

    def __init__(self, part: MirrorPart):
        self.part = part
        self.sign = tuple(-1 if i == part.axis else 1 for i in range(3))
        self.negated: set[str] = set()  # the coordinates whose sign flips

    def point(self, p: Vec3) -> Vec3:
        return (
            p[0] if self.sign[0] > 0 else _neg(p[0]),
            p[1] if self.sign[1] > 0 else _neg(p[1]),
            p[2] if self.sign[2] > 0 else _neg(p[2]),
        )

    def inertia(self, inertia: Mat3) -> Mat3:
        s = self.sign
        rows = [
            tuple(v if s[i] * s[j] > 0 else _neg(v) for j, v in enumerate(row))
            for i, row in enumerate(inertia)
        ]
        return (
            (rows[0][0], rows[0][1], rows[0][2]),
            (rows[1][0], rows[1][1], rows[1][2]),
            (rows[2][0], rows[2][1], rows[2][2]),
        )

    def body(self, b: Body) -> Body:
        if b.name not in self.part.bodies:
            return b
        shape = replace(b.shape, center=self.point(b.shape.center))
        return replace(
            b,
            com=self.point(b.com),
            inertia=self.inertia(b.inertia),
            direction=self.point(b.direction),
            shape=shape,
        )

    def joint(self, j: Joint) -> Joint:
        if j.name in self.part.at_tips:
            return replace(j, origin=self.point(j.origin))
        if j.child not in self.part.bodies:
            return j
        # at the tip of a body outside the instance: where that body's tip is
        origin = j.origin if j.name in self.part.on_outer_tips else self.point(j.origin)
        return replace(j, origin=origin, dofs=tuple(self.dof(d) for d in j.dofs))

    def dof(self, d: Dof) -> Dof:
        image = self.point(d.axis)
        if d.motion == "hinge":
            image = (_neg(image[0]), _neg(image[1]), _neg(image[2]))
        if image == d.axis:
            return d
        opposite = (_neg(d.axis[0]), _neg(d.axis[1]), _neg(d.axis[2]))
        if image != opposite:
            return replace(d, axis=image)
        self.negated.add(d.name)
        limits = None if d.limits is None else (_neg(d.limits[1]), _neg(d.limits[0]))
        return replace(d, initial=_neg(d.initial), initial_rate=_neg(d.initial_rate), limits=limits)

    def contact(self, c: Contact) -> Contact:
        if c.name not in self.part.contacts and c.name not in self.part.at_tips:
            return c
        if c.name in self.part.on_outer_tips:
            return c
        return replace(c, point=self.point(c.point))

    def actuator(self, a: Actuator) -> Actuator:
        if a.name not in self.part.actuators or a.dof not in self.negated:
            return a
        params = tuple((k, _neg(v) if k in ("rest", "setpoint") else v) for k, v in a.params)
        return replace(a, params=params)

    def stop(self, s: Stop) -> Stop:
        """A stop on a negated coordinate: at its mirrored limits, ``[-high, -low]``."""
        if s.dof not in self.negated:
            return s
        return replace(s, low=_neg(s.high), high=_neg(s.low))


def mirror_parts(
    parts: tuple[MirrorPart, ...],
    bodies: list[Body],
    joints: list[Joint],
    contacts: list[Contact],
    actuators: list[Actuator],
    stops: list[Stop],
    q0: list[float],
    v0: list[float],
) -> None:
    """Reflect each mirrored instance's parts of the model, in place."""
    for part in parts:
        m = Mirror(part)
        bodies[:] = [m.body(b) for b in bodies]
        joints[:] = [m.joint(j) for j in joints]
        contacts[:] = [m.contact(c) for c in contacts]
        actuators[:] = [m.actuator(a) for a in actuators]
        stops[:] = [m.stop(s) for s in stops]
        for d in (d for j in joints for d in j.dofs if d.name in m.negated):
            q0[d.q_index] = d.initial
            v0[d.v_index] = d.initial_rate
