"""Every documented member of every kind of thing reads that thing's member.

A member name two kinds share (a path's ``length`` and a body's constant ``length``) was
taken for the other kind's: ``route.length`` looked the path up as a body and failed with an
internal error (StopIteration). The members are the ones docs/language.md lists.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from legdsl.check.source import check_model
from legdsl.cli import main
from legdsl.ir import controller as ir
from legdsl.pipeline.compile import compile_model

ROOT = Path(__file__).resolve().parents[2]

CREATURE = """
creature probe {
  spatial
  gravity 9.81 m/s^2
  body trunk free {
    mass 10 kg  inertia (0.2, 0.4, 0.4) kg*m^2  length 0.4 m
    initial x = 0 m, y = 0 m, z = 1 m
  }
  body thigh on trunk via revolute hip at (0.05 m, 0.02 m, -0.03 m) {
    length 0.3 m  com 0.15 m  mass 0.8 kg  inertia (0.01, 0.01, 0.001) kg*m^2
  }
  body shank on thigh via prismatic slide at tip {
    length 0.5 m  com 0.25 m  mass 0.3 kg  inertia (0.006, 0.006, 0.0001) kg*m^2
  }
  contact toe on shank at tip
  leg main { joints hip, slide  foot toe }
  actuator leg_spring on slide spring(k = 3000 N/m, b = 5 N*s/m, rest = 0 m)
  actuator hip_servo on hip servo(kp = 150 N*m/rad, kv = 6 N*m*s/rad)
  actuator hip_motor on hip torque(max = 100 N*m)
  ground { normal spring(k = 3e4 N/m, b = 300 N*s/m)  tangent spring(k = 2e4 N/m, b = 200 N*s/m) }
}
"""

# the thing read for each row of the docs' table of members
READ_AS = {
    "leg, role": "main", "body": "trunk", "contact": "toe", "`com`": "com",
    "`terrain`": "terrain", "path": "route", "coordinate": "hip", "spring actuator": "leg_spring",
    "servo actuator": "hip_servo", "force or torque actuator": "hip_motor",
}  # fmt: skip
CONSTANTS = {"trunk": {"length": 0.4, "mass": 10.0, "com_x": 0.0, "com_y": 0.0, "com_z": 0.0},
             "hip": {"at_x": 0.05, "at_y": 0.02, "at_z": -0.03},
             "main": {"hip_at_x": 0.05, "hip_at_y": 0.02, "hip_at_z": -0.03}}  # fmt: skip


def documented_members() -> dict[str, list[str]]:
    """The thing read -> the members docs/language.md lists for its kind."""
    text = (ROOT / "docs" / "language.md").read_text()
    table = text.split("**Members** each kind of thing has:")[1].split("\n\n")[1]
    out: dict[str, list[str]] = {}
    for row in table.splitlines()[2:]:
        kind, members = row.strip("|").split("|")
        names = re.findall(r"`(\w+)`", members.split("(see")[0])
        out[READ_AS[kind.strip()]] = names
    assert set(out) == set(READ_AS.values())
    return out


def test_every_documented_member_reads_its_own_kind(tmp_path: Path) -> None:
    members = documented_members()
    assert "length" in members["route"] and "length" in members["trunk"]
    signals = [
        f"  signal s_{thing}_{member} = {thing}.{member}"
        for thing, names in members.items()
        for member in names
    ]
    path = tmp_path / "probe.leg"
    path.write_text(
        CREATURE
        + "controller c {\n  path route = circle(center = (0, 5) m, radius = 5 m)\n"
        + "\n".join(signals)
        + "\n  table { state A on time >= 0 s: hip_servo.setpoint = 0 deg }\n}\n"
    )
    controller = check_model(path).controller("c")
    for thing, names in members.items():
        for member in names:
            value = controller.signal(f"s_{thing}_{member}").value
            constant = CONSTANTS.get(thing, {}).get(member)
            if constant is not None:
                assert value == ir.Num(constant, value.type), (thing, member)
                continue
            assert isinstance(value, ir.Read), (thing, member, value)
            assert value.member == member
            read = value.thing
            assert (read.leg if isinstance(read, ir.Legs) else read.name) == thing
    compile_model(path)  # and each one lowers


def test_a_paths_length_is_its_length_on_a_run(tmp_path: Path) -> None:
    """A servo set to the path's length (31.4 m: a circle of radius 5 m) in deg per metre,
    the other to a body's length, holds its joint there."""
    path = tmp_path / "arms.leg"
    path.write_text("""
creature arms {
  planar
  gravity 0 m/s^2
  body base fixed at (0 m, 2 m) { mass 1 kg  inertia 0.1 kg*m^2  length 0.1 m }
  body a on base via revolute j { length 0.5 m  com 0.25 m  mass 1 kg  inertia 0.02 kg*m^2 }
  body b on base via revolute k { length 0.5 m  com 0.25 m  mass 1 kg  inertia 0.02 kg*m^2 }
  actuator sa on j servo(kp = 2000 N*m/rad, kv = 60 N*m*s/rad)
  actuator sb on k servo(kp = 2000 N*m/rad, kv = 60 N*m*s/rad)
}
controller c {
  path route = circle(center = (0, 5) m, radius = 5 m)
  table {
    state A on route.progress > route.length:
      sa.setpoint = route.length * 1 deg/m; sb.setpoint = a.length * 10 deg/m
  }
}
""")
    out = tmp_path / "run"
    args = ["run", str(path), "--controller", "c", "--time", "2", "--out", str(out)]
    assert main([*args, "--generated", str(tmp_path / "gen")]) == 0
    q = np.degrees(np.load(out / "trajectory.npz")["q"][-1])
    assert abs(q[0] - 10 * np.pi) < 1e-3  # 2 pi 5 m
    assert abs(q[1] - 5.0) < 1e-3
