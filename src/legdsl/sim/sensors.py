"""Sensor values for controllers: the signals of the member catalogue, read from a running simulation.

A controller's expressions refer to things like ``active.length`` or
``trunk.pitch_rate``; the lowered control module names each such value by a
*sensor key* (``leg.main.length``, ``body.trunk.pitch_rate``) and asks this
layer for exactly the keys it uses, once per control tick. Kinematics come
from the generated dynamics module; times (last stance and flight) are
tracked here from the contact flags.

Frames: world values are in world axes. A leg's ``foot_*`` members are the
foot relative to the centre of mass in the *heading frame* (world axes turned
by the root's yaw), so ``foot_x`` is the forward displacement of eq. (3).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any

from legdsl.ir.model import Model
from legdsl.ir.paths import PathSpec
from legdsl.sim import terrain_ahead
from legdsl.sim.path_tracking import PathTracker

Vec = tuple[float, float, float]


@dataclass
class _LegClock:
    """Touchdown and liftoff times of one foot, for the last stance and flight durations."""

    touching: bool = False
    touchdown: float = math.nan
    liftoff: float = math.nan
    stance: float = math.nan
    flight: float = math.nan


def _tick(clock: _LegClock, t: float, now: bool) -> None:
    """A touchdown or liftoff at ``t``, if ``now`` differs from what the clock knew."""
    if now and not clock.touching:
        if not math.isnan(clock.liftoff):
            clock.flight = t - clock.liftoff
        clock.touchdown = t
    elif clock.touching and not now:
        if not math.isnan(clock.touchdown):
            clock.stance = t - clock.touchdown
        clock.liftoff = t
    clock.touching = now


def rpy(r: tuple[float, ...], planar: bool = False) -> tuple[float, float, float]:
    """Roll, pitch, yaw of a row-major rotation R = Rz(yaw) Ry(pitch) Rx(roll).

    A planar creature turns about y alone, so its pitch is read over the whole turn, in
    (-180, 180] degrees: past 90 degrees the 3D reading folds (120 deg read as a roll and yaw
    of 180 and a pitch of 60), and a flip could not be followed."""
    if planar and r[8] < 0.0:  # past 90 degrees of pitch (below it, the 3D reading holds)
        s = max(-1.0, min(1.0, -r[6]))
        return 0.0, math.copysign(math.pi, s) - math.asin(s), 0.0
    return (
        math.atan2(r[7], r[8]),
        math.asin(max(-1.0, min(1.0, -r[6]))),
        math.atan2(r[3], r[0]),
    )


def euler_rates(
    rot: tuple[float, ...], omega: Vec, planar: bool = False
) -> tuple[float, float, float, float, float, float]:
    """``rpy`` and the angles' rates, from the world angular velocity (a planar creature's
    pitch rate past 90 degrees is its turning rate about y)."""
    roll, pitch, yaw = rpy(rot, planar)
    if planar and rot[8] < 0.0:
        return roll, pitch, yaw, 0.0, omega[1], 0.0
    # body-frame angular velocity: R^T omega
    bx = rot[0] * omega[0] + rot[3] * omega[1] + rot[6] * omega[2]
    by = rot[1] * omega[0] + rot[4] * omega[1] + rot[7] * omega[2]
    bz = rot[2] * omega[0] + rot[5] * omega[1] + rot[8] * omega[2]
    sr, cr = math.sin(roll), math.cos(roll)
    cp = math.cos(pitch)
    cp = cp if abs(cp) > 1e-9 else math.copysign(1e-9, cp)
    roll_rate = bx + (by * sr + bz * cr) * math.tan(pitch)
    pitch_rate = by * cr - bz * sr
    yaw_rate = (by * sr + bz * cr) / cp
    return roll, pitch, yaw, roll_rate, pitch_rate, yaw_rate


class Sensors:
    """Reads sensor keys from a simulation (anything with ``t``, ``q``, ``v``, ``dyn``, ``ground``)."""

    def __init__(self, model: Model):
        self.model = model
        self.body_index = {b.name: i for i, b in enumerate(model.bodies)}
        self.contact_index = {c.name: i for i, c in enumerate(model.contacts)}
        self.dof = {d.name: d for d in model.dofs}
        self.legs = {leg.name: leg for leg in model.legs}
        self.leg_hip = {leg.name: model.leg_hip(leg) for leg in model.legs}
        self.clocks = {c.name: _LegClock() for c in model.contacts}
        # a leg's own clock: it touches while any of its soles does (``foot sole, heel, toe``)
        self.leg_clocks = {leg.name: _LegClock() for leg in model.legs}
        self.leg_soles = {
            leg.name: [self.contact_index[c] for c in leg.soles] for leg in model.legs
        }
        self.paths: dict[str, PathTracker] = {}
        # integral(INPUT) (``integral.INPUT``): the machine's, which knows the commands
        self.integral: Callable[[str, float], float] | None = None

    def follow(self, specs: Iterable[PathSpec]) -> None:
        """The paths whose members (``path.NAME.lateral``, ...) the controller reads."""
        self.paths = {spec.name: PathTracker(spec) for spec in specs}

    def observe(self, t: float, touching: Iterable[bool]) -> None:
        """Update stance and flight clocks from the contact flags (call every control tick):
        each contact's, then each leg's from its soles."""
        flags = list(touching)
        clocks = list(self.clocks.values())
        for clock, now in zip(clocks, flags, strict=True):
            _tick(clock, t, bool(now))
        for name, clock in self.leg_clocks.items():
            _tick(clock, t, any(bool(flags[i]) for i in self.leg_soles[name]))

    def read(self, sim: Any, keys: Iterable[str]) -> dict[str, float]:
        """The values of ``keys`` now; kinematics are computed once and shared between keys."""
        cache: dict[str, Any] = {}
        return {key: self._value(sim, key, cache) for key in keys}

    # ------------------------------------------------------------ kinematics, computed once
    @staticmethod
    def _cached(cache: dict[str, Any], key: str, compute: Callable[[], Any]) -> Any:
        if key not in cache:
            cache[key] = compute()
        return cache[key]

    def _poses(self, sim: Any, cache: dict[str, Any]) -> Any:
        return self._cached(cache, "poses", lambda: sim.dyn.body_poses(sim.q))

    def _velocities(self, sim: Any, cache: dict[str, Any]) -> Any:
        return self._cached(cache, "vel", lambda: sim.dyn.body_velocities(sim.q, sim.v))

    def _feet(self, sim: Any, cache: dict[str, Any]) -> Any:
        return self._cached(
            cache,
            "feet",
            lambda: (sim.dyn.contact_positions(sim.q), sim.dyn.contact_velocities(sim.q, sim.v)),
        )

    def _com(self, sim: Any, cache: dict[str, Any]) -> Any:
        return self._cached(
            cache,
            "com",
            lambda: (sim.dyn.center_of_mass(sim.q), sim.dyn.center_of_mass_velocity(sim.q, sim.v)),
        )

    def _heading(self, sim: Any, cache: dict[str, Any]) -> tuple[float, float]:
        if "heading" not in cache:
            rot = self._poses(sim, cache)[0][1]
            yaw = 0.0 if self.model.planar else math.atan2(rot[3], rot[0])
            cache["heading"] = (math.cos(yaw), math.sin(yaw))
        return cache["heading"]

    def _to_heading(self, sim: Any, cache: dict[str, Any], vec: Vec) -> Vec:
        c, s = self._heading(sim, cache)
        return (c * vec[0] + s * vec[1], -s * vec[0] + c * vec[1], vec[2])

    # ------------------------------------------------------------ one key
    def _value(self, sim: Any, key: str, cache: dict[str, Any]) -> float:
        kind, _, rest = key.partition(".")
        name, _, member = rest.rpartition(".")
        if kind == "time":
            return float(sim.t)
        if kind == "coord":
            d = self.dof[name]
            return float(sim.q[d.q_index] if member == "value" else sim.v[d.v_index])
        if kind == "com":
            pos, vel = self._com(sim, cache)
            axis = "xyz".index(member[-1])
            return float(vel[axis] if member.startswith("v") else pos[axis])
        if kind == "contact":
            i = self.contact_index[name]
            if member == "touching":
                return 1.0 if sim.ground is not None and sim.ground.touching[i] else 0.0
            pos, vel = self._feet(sim, cache)
            axis = "xyz".index(member[-1])
            return float(vel[i][axis] if member.startswith("v") else pos[i][axis])
        if kind == "terrain":
            return self._terrain(sim, cache)[member]
        if kind == "act":
            return float(sim.actuators.by_name[name].get(member))
        if kind == "path":
            return self._path(sim, cache, name)[member]
        if kind == "body":
            return self._body(sim, cache, self.body_index[name], member)
        if kind == "leg":
            return self._leg(sim, cache, name, member)
        if kind == "integral" and self.integral is not None:
            return self.integral(rest, float(sim.t))
        raise KeyError(f"unknown sensor key {key!r}")

    def _path(self, sim: Any, cache: dict[str, Any], name: str) -> dict[str, float]:
        """The path's members for the centre of mass now (the tracker moves once per tick)."""
        key = f"path.{name}"
        if key not in cache:
            com = self._com(sim, cache)[0]
            cache[key] = self.paths[name].update(float(com[0]), float(com[1]))
        return cache[key]

    def _terrain(self, sim: Any, cache: dict[str, Any]) -> dict[str, float]:
        """The terrain ahead of the centre of mass along the heading, and under it."""
        if "terrain" not in cache:
            com = self._com(sim, cache)[0]
            x, y = float(com[0]), float(com[1])
            c, s = self._heading(sim, cache)
            ground = sim.ground
            found = dict(
                terrain_ahead.ahead(ground.ground.terrain if ground else (), x, y, math.atan2(s, c))
            )
            found["height"] = ground.height(x, y) if ground else 0.0
            cache["terrain"] = found
        return cache["terrain"]

    def _body(self, sim: Any, cache: dict[str, Any], i: int, member: str) -> float:
        pos, rot = self._poses(sim, cache)[i]
        if member in ("x", "y", "z"):
            return float(pos["xyz".index(member)])
        lin, ang = self._velocities(sim, cache)[i]
        if member in ("vx", "vy", "vz"):
            return float(lin["xyz".index(member[1])])
        angles = euler_rates(rot, ang, self.model.planar)
        order = ("roll", "pitch", "yaw", "roll_rate", "pitch_rate", "yaw_rate")
        return angles[order.index(member)]

    def _leg(self, sim: Any, cache: dict[str, Any], name: str, member: str) -> float:
        leg = self.legs[name]
        foot = self.contact_index[leg.foot]
        clock = self.leg_clocks[name]
        if member == "touching":
            return 1.0 if clock.touching else 0.0
        if member == "stance_time":
            return clock.stance
        if member == "flight_time":
            return clock.flight
        feet, feet_vel = self._feet(sim, cache)
        if member in ("length", "rate"):
            poses = self._poses(sim, cache)
            hip = self.leg_hip[name].point(poses)
            hip_vel = self.leg_hip[name].velocity(poses, self._velocities(sim, cache))
            d = [feet[foot][k] - hip[k] for k in range(3)]
            length = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
            if member == "length":
                return length
            dv = [feet_vel[foot][k] - hip_vel[k] for k in range(3)]
            return (d[0] * dv[0] + d[1] * dv[1] + d[2] * dv[2]) / length if length > 0 else 0.0
        com, com_vel = self._com(sim, cache)
        if member in ("hip_x", "hip_y", "hip_z"):
            hip = self.leg_hip[name].point(self._poses(sim, cache))
            rel = (hip[0] - com[0], hip[1] - com[1], hip[2] - com[2])
            return self._to_heading(sim, cache, rel)["xyz".index(member[-1])]
        if member in ("foot_x", "foot_y", "foot_z"):
            rel = (feet[foot][0] - com[0], feet[foot][1] - com[1], feet[foot][2] - com[2])
            return self._to_heading(sim, cache, rel)["xyz".index(member[-1])]
        rel_v = (
            feet_vel[foot][0] - com_vel[0],
            feet_vel[foot][1] - com_vel[1],
            feet_vel[foot][2] - com_vel[2],
        )
        return self._to_heading(sim, cache, rel_v)["xyz".index(member[-1])]
