"""A 3D biped with knees written from the docs (tests/good/outside/knee_biped.leg): ball hips,
a knee hinge whose rotary spring is the leg spring, and the shipped biped's `run` table with the
rests as knee angles. It compiles, runs the same on both backends, keeps its trunk up and level
and runs forward (docs/biped.md, "A biped with knees", has its 5 and 10 s runs)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from conftest import OUTSIDE, ROOT, outside_session
from runtime_helpers import assert_same, needs_c_compiler

from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions

LEG = OUTSIDE / "knee_biped.leg"

pytestmark = needs_c_compiler


def test_the_knee_biped_runs_the_same_on_both_backends_and_keeps_its_trunk_up() -> None:
    sess = outside_session(LEG.name)
    opts = RunOptions(duration=1.5)
    python = sess.run("run", ["speed=1m/s"], options=opts, backend="python").result
    c = sess.run("run", ["speed=1m/s"], options=opts, backend="c").result
    assert python.status == "ok", python.message
    assert_same(python, c)
    tr = python.trajectory
    assert tr.root_pos[:, 2].min() > 0.6  # trunk from 0.83 m, runs at 0.64-0.79 m
    assert np.abs(tr.root_rpy[:, :2]).max() < np.radians(8)  # within 3.5 deg in these 1.5 s
    assert 1.0 < tr.com[-1, 0] < 1.5  # running forward from rest towards 1 m/s


# The posture action knee_biped.leg wrote for itself before the standard library had one:
# eq. (4) with the knee spring's axial force, written out.
OWN_POSTURE = """  action posture(leg) {
    let f = -leg.spring.force / (leg.thigh.length * leg.shank.length * sin(leg.knee.value));
    leg.hip_servo.kp = 0 N*m/rad;
    leg.hip_servo.kv = 0 N*m*s/rad;
    leg.roll_servo.kp = 0 N*m/rad;
    leg.roll_servo.kv = 0 N*m*s/rad;
    leg.hip_motor.force = kp * trunk.pitch + kv * trunk.pitch_rate + f * (leg.foot_z * leg.hip_x - leg.foot_x * leg.hip_z);
    leg.roll_motor.force = kp_roll * trunk.roll + kv_roll * trunk.roll_rate + f * (leg.foot_y * leg.hip_z - leg.foot_z * leg.hip_y);
"""


def test_the_library_knee_posture_and_rotary_hop_are_the_knee_bipeds_own_laws(
    tmp_path: Path,
) -> None:
    """servo_posture_3d_knee and hop_apex_rotary (stdlib/raibert.leg) run the knee biped
    bit for bit as its own posture action and hop_apex(..., 1 rad) did."""
    text = LEG.read_text(encoding="utf-8")
    library_call = (
        "    servo_posture_3d_knee(leg, trunk, 0 rad, kp, kv, kp_roll, kv_roll, "
        "leg.thigh.length, leg.shank.length);\n"
    )
    start = text.index("  action posture(leg) {\n")
    assert text[start:].index(library_call) == len("  action posture(leg) {\n")
    own = (
        text[:start]
        + OWN_POSTURE
        + text[start + len("  action posture(leg) {\n") + len(library_call) :]
    )
    own = own.replace(
        "hop_apex_rotary(active, stand, height + apex_trim, 0 rad, 0.5 rad)",
        "hop_apex(active, stand, height + apex_trim, 0 rad, 0.5 rad, 1 rad)",
    )
    own = own.replace('use "../../../creatures/', f'use "{ROOT / "creatures"}/')
    assert "servo_posture_3d_knee(" not in own and "hop_apex_rotary(" not in own
    (tmp_path / "own").mkdir()
    own_leg = tmp_path / "own" / "knee_biped.leg"
    own_leg.write_text(own, encoding="utf-8")
    opts = RunOptions(duration=1.0)
    library = outside_session(LEG.name)
    written = RunSession.from_file(own_leg, generated=tmp_path / "own_gen")
    a = library.run("run", ["speed=1m/s"], options=opts, backend="python").result
    b = written.run("run", ["speed=1m/s"], options=opts, backend="python").result
    assert a.status == b.status == "ok", (a.message, b.message)
    assert a.trajectory.root_pos.shape == b.trajectory.root_pos.shape
    assert_same(a, b)
    assert a.trajectory.com[-1, 0] > 0.5  # it ran: stances, and the posture servo in them
