"""Ground contact as the paper models it (Raibert & Hodgins 1991, "Modeling").

Each foot contact point meets the ground through four spring-damper sets:
one along the surface normal, two tangent to the surface, and (in 3D) one
torsional about the normal. The tangential and torsional springs pull towards
*anchors* set where the foot first touches the ground in each support
period. The normal spring is linear, or the nonlinear paw pad of eq. (6).
With no friction coefficient the foot never slips (the paper's assumption);
with one, the tangential force is held inside the Coulomb cone and the
anchor follows the sliding foot.

Touchdown and liftoff change only at step boundaries (``update``); within a
step (all stages of RK4) the forces use the status at the step's start.
The terrain is a height field with flat tops (a step, boxes) or one inclined
plane (a slope); the side faces of steps and boxes are not modelled.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from legdsl.ir.model import Ground, Pad

Vec = tuple[float, float, float]
# The pad of eq. (6) is singular when fully compressed; past this fraction of
# its thickness it continues with the slope it has there.
PAD_LINEAR_FROM = 0.9


@dataclass
class ContactEvent:
    t: float
    kind: str  # touchdown | liftoff
    contact: str


def pad_force(pad: Pad, depth: float) -> float:
    """Eq. (6) for a penetration ``depth`` = -z > 0: f = k (T / (T + z) - 1)."""
    thickness = pad.thickness
    d = min(depth, PAD_LINEAR_FROM * thickness)
    f = pad.k * (thickness / (thickness - d) - 1.0)
    if depth > d:
        slope = pad.k * thickness / (thickness - d) ** 2
        f += slope * (depth - d)
    return f


class GroundContact:
    """State and forces of every foot contact on the ground."""

    def __init__(self, ground: Ground, names: tuple[str, ...], planar: bool):
        self.ground = ground
        self.names = names
        self.planar = planar
        n = len(names)
        self.touching = [False] * n
        self.anchor: list[Vec] = [(0.0, 0.0, 0.0)] * n
        self.yaw_anchor = [0.0] * n
        self.slipping = [False] * n
        self._slope = next((t for t in ground.terrain if t.kind == "slope"), None)
        self._flats = [t for t in ground.terrain if t.kind in ("step", "box")]

    # ------------------------------------------------------------ terrain
    def surface(self, x: float, y: float) -> tuple[Vec, Vec]:
        """A point on the surface under (x, y) and the unit normal there."""
        if self._slope is not None:
            a = self._slope.get("angle")
            return (0.0, 0.0, 0.0), (-math.sin(a), 0.0, math.cos(a))
        h = 0.0
        for t in self._flats:
            under = (
                x >= t.get("x")
                if t.kind == "step"
                else t.get("x0") <= x <= t.get("x1") and t.get("y0") <= y <= t.get("y1")
            )
            if under:
                h = max(h, t.get("height"))
        return (x, y, h), (0.0, 0.0, 1.0)

    def height(self, x: float, y: float) -> float:
        (ox, oy, oz), (nx, ny, nz) = self.surface(x, y)
        return oz - (nx * (x - ox) + ny * (y - oy)) / nz

    def _tangents(self, n: Vec) -> tuple[Vec, Vec]:
        # t1 lies in the x-z plane (the only tangent of a planar creature), t2 = n x t1.
        t1 = (n[2], 0.0, -n[0])
        t2 = (n[1] * t1[2] - n[2] * t1[1], n[2] * t1[0] - n[0] * t1[2], n[0] * t1[1] - n[1] * t1[0])
        return t1, t2

    def directions(self, p: Vec) -> list[Vec]:
        """The directions of the ground's springs on a contact at ``p``: the surface's normal
        under it, then its tangents (one for a planar creature)."""
        n = self.surface(p[0], p[1])[1]
        t1, t2 = self._tangents(n)
        return [n, t1] if self.planar else [n, t1, t2]

    def depth(self, p: Vec) -> tuple[float, Vec]:
        o, n = self.surface(p[0], p[1])
        return n[0] * (o[0] - p[0]) + n[1] * (o[1] - p[1]) + n[2] * (o[2] - p[2]), n

    # ------------------------------------------------------------ forces
    def force(self, i: int, p: Vec, pv: Vec) -> Vec:
        """World force on contact ``i`` at position ``p`` moving at ``pv``."""
        if not self.touching[i]:
            return (0.0, 0.0, 0.0)
        d, n = self.depth(p)
        if d <= 0.0:
            return (0.0, 0.0, 0.0)
        g = self.ground
        vn = pv[0] * n[0] + pv[1] * n[1] + pv[2] * n[2]
        spring = pad_force(g.normal, d) if isinstance(g.normal, Pad) else g.normal.k * d
        fn = max(0.0, spring - g.normal.b * vn)
        t1, t2 = self._tangents(n)
        a = self.anchor[i]
        e = (p[0] - a[0], p[1] - a[1], p[2] - a[2])
        k, b = g.tangent.k, g.tangent.b
        f1 = -k * (e[0] * t1[0] + e[1] * t1[1] + e[2] * t1[2]) - b * (
            pv[0] * t1[0] + pv[1] * t1[1] + pv[2] * t1[2]
        )
        f2 = 0.0
        if not self.planar:
            f2 = -k * (e[0] * t2[0] + e[1] * t2[1] + e[2] * t2[2]) - b * (
                pv[0] * t2[0] + pv[1] * t2[1] + pv[2] * t2[2]
            )
        mu = g.friction
        if mu is not None:
            ft = math.hypot(f1, f2)
            if ft > mu * fn and ft > 0.0:
                scale = mu * fn / ft
                f1, f2 = f1 * scale, f2 * scale
        return (
            fn * n[0] + f1 * t1[0] + f2 * t2[0],
            fn * n[1] + f1 * t1[1] + f2 * t2[1],
            fn * n[2] + f1 * t1[2] + f2 * t2[2],
        )

    def yaw(self, rot: Sequence[float]) -> float:
        """A body's turn about the ground's normal, which the torsion spring holds: the angle of
        its x axis (rotation matrix ``rot``, row by row) from t1 in the ground's plane; on level
        ground its yaw, atan2(R10, R00). (t1 x t2 is the normal: the angle grows as it turns
        about the normal.)"""
        if self._slope is None:
            return math.atan2(rot[3], rot[0])
        a = self._slope.get("angle")
        return math.atan2(rot[3], math.cos(a) * rot[0] + math.sin(a) * rot[6])

    def about_normal(self, jac_w: Sequence[Sequence[float]]) -> Sequence[float]:
        """The row of a body's angular Jacobian (its x, y and z rows) about the ground's normal:
        its rate about the normal, and the torque there as generalized forces."""
        if self._slope is None:
            return jac_w[2]
        a = self._slope.get("angle")
        nx, nz = -math.sin(a), math.cos(a)  # the slope's normal, as surface() has it
        return [nx * x + nz * z for x, z in zip(jac_w[0], jac_w[2], strict=True)]

    def torsion(self, i: int, yaw: float, yaw_rate: float) -> float:
        """Torque about the normal on the contact's body, pulling its yaw back to the anchor."""
        sd = self.ground.torsion
        if sd is None or not self.touching[i]:
            return 0.0
        err = math.remainder(yaw - self.yaw_anchor[i], math.tau)
        return -sd.k * err - sd.b * yaw_rate

    # ------------------------------------------------------------ events
    def near(self, positions: list[Vec]) -> bool:
        """Whether a foot touches, or is at or under the ground: whether ``update`` and the
        forces will read any contact's velocity or yaw."""
        return any(self.touching) or any(self.depth(p)[0] > 0.0 for p in positions)

    def update(
        self, t: float, positions: list[Vec], velocities: list[Vec], yaws: list[float] | None = None
    ) -> list[ContactEvent]:
        """Touchdowns, liftoffs and friction slip, at a step boundary."""
        events = []
        for i, p in enumerate(positions):
            d, n = self.depth(p)
            if d > 0.0 and not self.touching[i]:
                self.touching[i] = True
                self.anchor[i] = (p[0] + d * n[0], p[1] + d * n[1], p[2] + d * n[2])
                self.yaw_anchor[i] = yaws[i] if yaws is not None else 0.0
                events.append(ContactEvent(t, "touchdown", self.names[i]))
            elif d <= 0.0 and self.touching[i]:
                self.touching[i] = False
                self.slipping[i] = False
                events.append(ContactEvent(t, "liftoff", self.names[i]))
            elif self.touching[i] and self.ground.friction is not None:
                self._slip(i, p, velocities[i], d, n)
        return events

    def _slip(self, i: int, p: Vec, pv: Vec, d: float, n: Vec) -> None:
        """Outside the friction cone the foot slides (``force`` holds its force to the cone), and
        where the tangential spring alone pulls harder than the cone the anchor follows the foot,
        straight towards it, until the spring holds exactly the cone's force. It never moves
        away from the foot: the spring then holds (mu fn)^2 / (2 k), what it can give back. (An
        anchor put where spring and damper together held the cone's force was ahead of a foot
        sliding faster than mu fn / b: the spring pushed against its damper and "held" energy
        no force had stored, 11 J for a 5 N touch at 4.8 m/s.)"""
        g = self.ground
        f = self.force(i, p, pv)
        fn = f[0] * n[0] + f[1] * n[1] + f[2] * n[2]
        t1, t2 = self._tangents(n)
        a = self.anchor[i]
        e = (p[0] - a[0], p[1] - a[1], p[2] - a[2])
        k, b = g.tangent.k, g.tangent.b
        s1 = -k * _dot(e, t1)
        s2 = 0.0 if self.planar else -k * _dot(e, t2)
        f1 = s1 - b * _dot(pv, t1)
        f2 = 0.0 if self.planar else s2 - b * _dot(pv, t2)
        assert g.friction is not None
        limit = g.friction * fn
        self.slipping[i] = math.hypot(f1, f2) > limit
        st = math.hypot(s1, s2)
        if not st > limit or k <= 0.0:
            return
        scale = limit / st
        # The spring's force scaled to the cone's, -k (p - a) . t = s scale: the anchor's offset.
        off1 = s1 * scale / k
        off2 = s2 * scale / k
        base = (p[0] + d * n[0], p[1] + d * n[1], p[2] + d * n[2])
        self.anchor[i] = (
            base[0] + off1 * t1[0] + off2 * t2[0],
            base[1] + off1 * t1[1] + off2 * t2[1],
            base[2] + off1 * t1[2] + off2 * t2[2],
        )

    def elastic_energy(self, positions: list[Vec]) -> float:
        """Energy stored in the normal and tangential ground springs (torsion is not counted)."""
        g = self.ground
        total = 0.0
        for i, p in enumerate(positions):
            if not self.touching[i]:
                continue
            d, n = self.depth(p)
            if d <= 0.0:
                continue
            if isinstance(g.normal, Pad):
                total += _pad_energy(g.normal, d)
            else:
                total += 0.5 * g.normal.k * d * d
            a = self.anchor[i]
            e = (p[0] - a[0], p[1] - a[1], p[2] - a[2])
            t1, t2 = self._tangents(n)
            e1 = _dot(e, t1)
            e2 = 0.0 if self.planar else _dot(e, t2)
            total += 0.5 * g.tangent.k * (e1 * e1 + e2 * e2)
        return total


def _dot(a: Vec, b: Vec) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _pad_energy(pad: Pad, depth: float) -> float:
    """Integral of eq. (6) from 0 to ``depth`` (with the linear continuation past the cap)."""
    t = pad.thickness
    d = min(depth, PAD_LINEAR_FROM * t)
    energy = pad.k * (-t * math.log((t - d) / t) - d)
    if depth > d:
        f0 = pad.k * (t / (t - d) - 1.0)
        slope = pad.k * t / (t - d) ** 2
        x = depth - d
        energy += f0 * x + 0.5 * slope * x * x
    return energy
