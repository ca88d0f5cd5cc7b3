"""A hopper on a paw-pad ground with a 4 cm step at x = 1.5 m (reported from outside): its
stance toe slides over the step's edge from the lower ground, is under the step's top at once
(the ground has no side faces), and is thrown out with some 9e4 N, 800 times its weight; the
energy check tells it as a divergence (exit 3). Its likely cause used to be "the state grew
without bound; try a smaller step ... or --integrator rk4", which would not help: the energy
check looked at the samples before the push, and the push is on a foot that was down already.
It names the step's edge now (``legdsl.sim.causes.under_edge``), from the feet's positions at
the last samples, at the default record rate (the toe is thrown out between two samples) and
at every step (the push recorded)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from runtime_helpers import needs_c_compiler

from legdsl.cli import main

LEG = """\
# A planar one-legged hopper, the machine the paper's control was first built
# for (Raibert 1986): a body and one telescoping leg with a hip. It is not in
# Table 3; its numbers are chosen, on the scale of the MIT planar hopper.
# Its controller, `hop`, is the Figure 4 state machine for one leg, written
# with the standard library's eq. (2), (3) and (4) actions.
use raibert

creature hstep {
  planar
  gravity 9.81 m/s^2

  body body free {
    mass 10 kg  inertia 0.4 kg*m^2
    shape box(0.5 m, 0.15 m)
    initial x = 0 m, z = 0.95 m, pitch = 0 deg
    color "#506880"
  }
  # The upper leg is the actuator housing; the lower leg slides in it.
  body thigh on body via revolute hip at (0 m, 0 m) {
    length 0.3 m  com 0.15 m  mass 0.8 kg  inertia 0.01 kg*m^2
    shape cylinder(0.04 m)
    limits -60 deg to 60 deg
    color "#506880"
  }
  body shank on thigh via prismatic leg at tip {
    length 0.5 m  com 0.25 m  mass 0.3 kg  inertia 0.006 kg*m^2
    shape cylinder(0.012 m)
    limits -0.25 m to 0.1 m
    color "#303030"
  }
  contact toe on shank at tip

  leg main {
    joints hip, leg
    foot toe
    alias spring = leg_spring, hip_servo = hip_servo, hip_motor = hip_motor
  }

  actuator leg_spring on leg spring(k = 3000 N/m, b = 5 N*s/m, rest = 0 m)
  actuator hip_servo on hip servo(kp = 150 N*m/rad, kv = 6 N*m*s/rad, max = 100 N*m)
  actuator hip_motor on hip torque(max = 100 N*m)

  ground {
    normal pad(k = 600 N, thickness = 2 cm, b = 300 N*s/m)
    tangent spring(k = 2e4 N/m, b = 200 N*s/m)
    friction none
    terrain step(x = 1.5 m, height = 4 cm)
  }
}

# Figure 4 for one leg: the machine waits in each state for the next one's event.
controller hop {
  input speed = 1 m/s          # the animator's commands
  input height = 1.0 m         # the centre of mass at the top of each hop
  param k_speed = 0.06 s       # eq. (3) gain
  param stance_guess = 0.2 s   # Ts before the first stance is measured
  param kp = 150 N*m/rad       # eq. (4)
  param kv = 15 N*m*s/rad
  param swing_kp = 150 N*m/rad
  param swing_kv = 6 N*m*s/rad
  param stroke = 3 cm          # eq. (2): the nominal rest step of the leg spring in thrust
  param k_height = 0.3         # eq. (2): more stroke per metre of missing height
  param k_apex = 0.5           # eq. (2) learned: fraction of each hop's apex error integrated into the aim...
  param apex_limit = 0.5 m     # ...the learned aim staying within this of `height`
  param k_trim = 0.5           # speed trim: fraction of each stride's speed error integrated
  param full = 0.79 m          # leg length at which thrust is over
  roles active = main
  # Each stride aims at the command, or, when that is more than `reach` from the last
  # stride's aim, `reach` closer to it: `max_step` from standing or hopping in place (the
  # aim 0), `moving_step` once moving. So 4 m/s from standing comes in ten strides, and
  # 1.5 m/s in one. Placed for 2 m/s at once, the hopper fell in its first stride; aiming
  # 1.5 m/s further every stride, in its second from 2.5 m/s up; 0.4 m/s further once
  # moving, when asked for 3 m/s while hopping in place. The aim is recorded at liftoff
  # and the foot placement reads it (as the biped's `run` does). A command within reach
  # runs exactly as the command itself would, to the bit (`speed_aim` sorts where `speed`
  # did, so the placement's sum is printed in the same order).
  param max_step = 1.5 m/s
  param moving_step = 0.3 m/s
  signal reach = select(abs(speed_aim) < 1 mm/s, max_step, moving_step)
  signal next_aim = select(abs(speed - speed_aim) <= reach, speed, speed_aim + clamp(speed - speed_aim, -reach, reach))

  table {
    state FLIGHT      on liftoff(active):       relax(active, 0 m); swing(active, swing_kp, swing_kv); record speed_aim = next_aim; trim_speed(next_aim, k_trim); learn_apex(height, k_apex, apex_limit); place_foot(active, speed_aim + speed_trim, k_speed, stance_guess)
    state LOADING     on touchdown(active):     free_hip(active)
    state COMPRESSION on active.rate < 0:       servo_pitch(active, body, 0 deg, kp, kv)
    state THRUST      on active.rate > 0:       hop_apex(active, 0 m, height + apex_trim, 0 m, 3 * stroke, 1); servo_pitch(active, body, 0 deg, kp, kv)
    state UNLOADING   on active.length > full:  relax(active, 0 m); free_hip(active)
  }
}
"""
EDGE = (
    "Likely cause: contact 'toe' went under the edge of a step (the ground under it rose 4 cm "
    "between t = "
)
TOPS = "the ground has their top faces only: a foot under a top's edge is under its top at once"


@needs_c_compiler
def test_the_toe_pushed_under_the_steps_edge_is_the_likely_cause(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    leg = tmp_path / "hstep.leg"
    leg.write_text(LEG)
    gen, out = tmp_path / "gen", tmp_path / "out"
    assert main(["run", str(leg), "--controller", "hop", "--time", "3", "--backend", "c",
                 "--generated", str(gen), "--out", str(out)]) == 3  # fmt: skip
    err = capsys.readouterr().err
    assert "the total energy rose from 116.9 J at t = 1.4768 s to 2234 J at t = 1.4820 s" in err
    assert EDGE + "1.4768 s and t = 1.4820 s) and was pushed with 8.86e+04 N at least" in err
    assert "813 times the creature's weight, and was thrown out; " + TOPS in err
    assert "the state grew without bound" not in err
    cause = json.loads((out / "run.json").read_text())["cause"]
    assert EDGE in cause and "contact 'toe'" in cause
