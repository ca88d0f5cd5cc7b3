"""``legdsl.sim.sensors``: Euler angles and rates, leg clocks, and the members of the catalogue,
read from the checked-in generated modules of the shipped creatures (no compiling, no run)."""

from __future__ import annotations

import math
import random
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import pytest
from conftest import outside_session, shipped_dynamics, shipped_model

from legdsl.sim.sensors import Sensors, euler_rates

ROOT = Path(__file__).resolve().parents[2]


def _rot(roll: float, pitch: float, yaw: float) -> tuple[float, ...]:
    """R = Rz(yaw) Ry(pitch) Rx(roll), row-major."""
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    return (
        cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,
        sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,
        -sp, cp * sr, cp * cr,
    )  # fmt: skip


def _omega(angles: Any, t: float, h: float = 1e-6) -> tuple[float, float, float]:
    """World angular velocity of R(angles(t)) by central differences: skew(w) = R' R^T."""
    a, b = _rot(*angles(t + h)), _rot(*angles(t - h))
    r = _rot(*angles(t))
    rdot = [(a[i] - b[i]) / (2 * h) for i in range(9)]

    def w(i: int, j: int) -> float:  # (R' R^T)[i][j]
        return sum(rdot[3 * i + k] * r[3 * j + k] for k in range(3))

    return (w(2, 1), w(0, 2), w(1, 0))


@pytest.mark.parametrize("seed", range(5))
def test_euler_rates_are_the_derivatives_of_the_angles(seed: int) -> None:
    rng = random.Random(seed)
    start = [rng.uniform(-1.0, 1.0), rng.uniform(-1.2, 1.2), rng.uniform(-3.0, 3.0)]
    rate = [rng.uniform(-2.0, 2.0) for _ in range(3)]

    def angles(t: float) -> tuple[float, float, float]:
        return (start[0] + rate[0] * t, start[1] + rate[1] * t, start[2] + rate[2] * t)

    got = euler_rates(_rot(*angles(0.0)), _omega(angles, 0.0))
    assert got[:3] == pytest.approx(start, abs=1e-9)  # roll, pitch, yaw recovered
    assert got[3:] == pytest.approx(rate, abs=1e-6)  # and their rates


def test_euler_rates_of_a_pure_pitch_and_a_pure_yaw() -> None:
    assert euler_rates(_rot(0.0, 0.3, 0.0), (0.0, 2.0, 0.0)) == pytest.approx(
        (0.0, 0.3, 0.0, 0.0, 2.0, 0.0)
    )
    # a yaw rate about the world z, whatever the pitch
    assert euler_rates(_rot(0.0, 0.4, 1.0), (0.0, 0.0, 1.5))[3:] == pytest.approx(
        (0.0, 0.0, 1.5), abs=1e-12
    )


def _sim(name: str, q: list[float], v: list[float], **kw: Any) -> SimpleNamespace:
    return SimpleNamespace(t=0.0, q=q, v=v, dyn=shipped_dynamics(name), ground=None, **kw)


def test_leg_clocks_give_the_last_stance_and_flight() -> None:
    model = shipped_model("hopper")
    sensors = Sensors(model)
    sim = _sim("hopper", list(model.q0), list(model.v0))
    keys = ["leg.main.stance_time", "leg.main.flight_time", "leg.main.touching"]

    def read(t: float, touching: bool) -> list[float]:
        sensors.observe(t, [touching])
        return list(sensors.read(sim, keys).values())

    assert all(math.isnan(x) for x in read(0.0, False)[:2])  # nothing complete yet
    assert read(0.1, True)[2] == 1.0
    after_first = read(0.35, False)
    assert after_first[0] == pytest.approx(0.25) and math.isnan(after_first[1])
    assert after_first[2] == 0.0
    assert read(0.6, True)[:2] == pytest.approx([0.25, 0.25])  # flight 0.35 -> 0.6
    assert read(0.7, True)[:2] == pytest.approx([0.25, 0.25])  # still in stance: unchanged
    assert read(0.75, False)[:2] == pytest.approx([0.15, 0.25])  # stance 0.6 -> 0.75


def _hopper_state() -> tuple[list[float], list[float]]:
    q = [0.1, 0.9, 0.2, -0.3, 0.05]  # x, z, pitch, hip, leg
    v = [0.7, -0.4, 0.9, -1.3, 0.6]
    return q, v


@pytest.mark.parametrize(
    ("rate", "value"),
    [
        ("com.vx", "com.x"),
        ("com.vz", "com.z"),
        ("leg.main.rate", "leg.main.length"),
        ("body.body.pitch_rate", "body.body.pitch"),
        ("body.thigh.vz", "body.thigh.z"),
        ("contact.toe.vx", "contact.toe.x"),
        ("coord.hip.rate", "coord.hip.value"),
    ],
)
def test_rates_are_the_derivatives_of_their_values(rate: str, value: str) -> None:
    model = shipped_model("hopper")
    assert model.q_names == tuple(d.name for d in model.dofs)  # planar: dq/dt = v
    sensors = Sensors(model)
    q, v = _hopper_state()
    h = 1e-6

    def at(step: float) -> float:
        moved = [qi + step * vi for qi, vi in zip(q, v, strict=True)]
        return sensors.read(_sim("hopper", moved, v), [value])[value]

    numeric = (at(h) - at(-h)) / (2 * h)
    assert sensors.read(_sim("hopper", q, v), [rate])[rate] == pytest.approx(numeric, abs=1e-6)
    assert abs(numeric) > 1e-3  # the state moves it: the check is not 0 == 0


def test_leg_length_is_the_hip_to_foot_distance_and_com_is_the_models() -> None:
    model = shipped_model("hopper")
    dyn = shipped_dynamics("hopper")
    q, v = _hopper_state()
    got = Sensors(model).read(_sim("hopper", q, v), ["leg.main.length", "com.x", "com.z"])
    hip = model.leg_hip(model.legs[0]).point(dyn.body_poses(q))
    foot = dyn.contact_positions(q)[0]
    assert got["leg.main.length"] == pytest.approx(math.dist(hip, foot))
    com = dyn.center_of_mass(q)
    assert (got["com.x"], got["com.z"]) == pytest.approx((com[0], com[2]))
    # the centre of mass is the mass-weighted mean of something between the body and the foot
    assert min(hip[2], foot[2]) - 0.5 < got["com.z"] < q[1] + 0.5


def test_kinematics_are_computed_once_per_read() -> None:
    model = shipped_model("hopper")
    dyn = shipped_dynamics("hopper")
    calls: dict[str, int] = {}

    def counted(name: str) -> Any:
        def call(*args: Any) -> Any:
            calls[name] = calls.get(name, 0) + 1
            return getattr(dyn, name)(*args)

        return call

    names = ("body_poses", "body_velocities", "contact_positions", "center_of_mass")
    fake = SimpleNamespace(**{n: counted(n) for n in names})
    fake.contact_velocities = dyn.contact_velocities
    fake.center_of_mass_velocity = dyn.center_of_mass_velocity
    q, v = _hopper_state()
    sim = SimpleNamespace(t=0.0, q=q, v=v, dyn=fake, ground=None)
    keys = ["body.body.pitch", "body.body.x", "leg.main.length", "leg.main.hip_x", "com.x"]
    keys += ["leg.main.foot_x", "contact.toe.z", "body.body.pitch_rate"]
    Sensors(model).read(sim, keys)
    assert calls == dict.fromkeys(names, 1)


def _yawed(model: Any, yaw: float) -> list[float]:
    q = list(model.q0)
    q[model.q_names.index("qw")] = math.cos(yaw / 2)
    q[model.q_names.index("qz")] = math.sin(yaw / 2)
    q[model.q_names.index("hip_l_y")] = 0.3  # a leg swung forward, so foot_x is not 0
    q[model.q_names.index("hip_l_x")] = 0.1
    return q


def test_leg_members_are_in_the_heading_frame() -> None:
    model = shipped_model("biped")
    sensors = Sensors(model)
    assert model.q0[model.q_names.index("qw")] == 1.0  # it starts facing +x
    v = [0.0] * model.nv
    v[model.v_names.index("hip_l_y")] = 1.0  # the leg swings; the trunk does not turn
    members = ["foot_x", "foot_y", "foot_z", "hip_x", "hip_y", "hip_z", "foot_vx", "foot_vy"]
    keys = [f"leg.left.{m}" for m in members] + ["com.x", "com.y", "contact.toe_l.x"]
    keys += ["contact.toe_l.y", "body.trunk.yaw"]
    ahead = sensors.read(_sim("biped", _yawed(model, 0.0), v), keys)
    turned = sensors.read(_sim("biped", _yawed(model, math.pi / 2), v), keys)
    for m in members:  # turning the whole creature leaves its heading-frame members alone
        assert turned[f"leg.left.{m}"] == pytest.approx(ahead[f"leg.left.{m}"], abs=1e-9), m
    assert abs(ahead["leg.left.foot_x"]) > 0.01 and abs(ahead["leg.left.foot_vx"]) > 0.01
    assert turned["body.trunk.yaw"] == pytest.approx(math.pi / 2)
    # in world axes the foot, relative to the centre of mass, turned a quarter left
    rel = (ahead["contact.toe_l.x"] - ahead["com.x"], ahead["contact.toe_l.y"] - ahead["com.y"])
    rel_turned = (
        turned["contact.toe_l.x"] - turned["com.x"],
        turned["contact.toe_l.y"] - turned["com.y"],
    )
    assert rel_turned == pytest.approx((-rel[1], rel[0]), abs=1e-9)
    assert (ahead["leg.left.foot_x"], ahead["leg.left.foot_y"]) == pytest.approx(rel, abs=1e-9)


def test_contact_touching_actuators_time_and_unknown_keys() -> None:
    model = shipped_model("hopper")
    sensors = Sensors(model)
    spring = SimpleNamespace(get=lambda member: {"force": 12.5, "k": 2000.0}[member])
    q, v = _hopper_state()
    sim = _sim("hopper", q, v, actuators=SimpleNamespace(by_name={"leg_spring": spring}))
    sim.t = 1.25
    keys = ["contact.toe.touching", "act.leg_spring.force", "act.leg_spring.k", "time"]
    assert list(sensors.read(sim, keys).values()) == [0.0, 12.5, 2000.0, 1.25]  # no ground
    sim.ground = SimpleNamespace(touching=[True])
    assert sensors.read(sim, ["contact.toe.touching"]) == {"contact.toe.touching": 1.0}
    with pytest.raises(KeyError, match="unknown sensor key 'wind.speed'"):
        sensors.read(sim, ["wind.speed"])


def test_a_spatial_leg_rate_is_the_derivative_of_its_length() -> None:
    model = shipped_model("biped")
    sensors = Sensors(model)
    q = _yawed(model, 0.4)
    v = [0.0] * model.nv  # the trunk still, every joint of the left leg moving
    joints = {"hip_l_x": 0.8, "hip_l_y": -1.1, "hip_l_z": 0.5, "leg_l": 0.3}
    dofs = {d.name: d for d in model.dofs}
    for name, rate in joints.items():
        v[dofs[name].v_index] = rate
    h = 1e-6

    def length(step: float) -> float:
        moved = list(q)
        for name, rate in joints.items():
            moved[dofs[name].q_index] += step * rate
        return sensors.read(_sim("biped", moved, v), ["leg.left.length"])["leg.left.length"]

    numeric = (length(h) - length(-h)) / (2 * h)
    got = sensors.read(_sim("biped", q, v), ["leg.left.rate"])["leg.left.rate"]
    assert got == pytest.approx(numeric, abs=1e-6) and abs(numeric) > 1e-3


def test_a_leg_that_only_slides_is_measured_from_where_the_slide_sits(tmp_path: Path) -> None:
    """The pogo's leg is one prismatic joint: its hip point is the joint's place on the body,
    not the rod's origin (which slides with the leg: a length that never changed). The rate
    is the derivative of the length, the body turning and moving too."""
    session = outside_session("pogo.leg")
    model, dyn = session.model, session.dynamics
    hip = model.leg_hip(model.legs[0])
    assert hip.at is not None and model.bodies[hip.body].name == "body"
    q, v = [0.1, 0.9, 0.2, -0.05], [0.7, -0.4, 0.9, 0.6]  # x, z, pitch, leg
    sensors = Sensors(model)

    def read(qs: list[float], key: str) -> float:
        sim = SimpleNamespace(t=0.0, q=qs, v=v, dyn=dyn, ground=None)
        return sensors.read(sim, [key])[key]

    # the rod's tip from the joint: its length (0.6 m) plus the slide
    assert read(q, "leg.main.length") == pytest.approx(0.6 + q[3])
    h = 1e-6
    moved = [[qi + step * vi for qi, vi in zip(q, v, strict=True)] for step in (h, -h)]
    numeric = (read(moved[0], "leg.main.length") - read(moved[1], "leg.main.length")) / (2 * h)
    assert read(q, "leg.main.rate") == pytest.approx(numeric, abs=1e-6)
    assert read(q, "leg.main.rate") == pytest.approx(v[3])
