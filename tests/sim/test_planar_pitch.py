"""A planar creature's pitch is read over the whole turn, in (-180, 180] degrees, by its
controllers and in its recording, on both backends alike: the 3D reading folds past 90
degrees (120 read as 60, with roll and yaw of 180 and the rate's sign turned), so a flip
could be neither followed nor measured. Below 90 degrees the reading is the 3D one, bit for
bit (every shipped planar run is unchanged)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from legdsl.pipeline.session import RunSession
from legdsl.sim.recorder import rpy
from legdsl.sim.run_loop import RunOptions
from legdsl.sim.sensors import euler_rates

TUMBLE = """\
# A planar block tumbling high in the air at one turn a second
creature tumble {
  planar
  body trunk free {
    mass 2 kg  inertia 0.1 kg*m^2
    shape box(0.3 m, 0.1 m)
    initial x = 0 m, z = 20 m, pitch = 0 deg
    velocity pitch = 360 deg/s
  }
}

controller watch {
  table {
    state TURNING on trunk.pitch < 90 deg:
    state PAST    on trunk.pitch > 100 deg and trunk.pitch_rate > 300 deg/s:
  }
}
"""


def _about_y(angle: float) -> tuple[float, ...]:
    c, s = math.cos(angle), math.sin(angle)
    return (c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)


@pytest.mark.parametrize("degrees", [-179, -150, -91, -60, 0, 45, 89, 91, 120, 179, 180])
def test_a_planar_pitch_reads_as_the_angle_turned(degrees: int) -> None:
    angle = math.radians(degrees)
    roll, pitch, yaw, roll_rate, pitch_rate, yaw_rate = euler_rates(
        _about_y(angle), (0.0, 5.0, 0.0), planar=True
    )
    assert (roll, yaw, roll_rate, yaw_rate) == (0.0, 0.0, 0.0, 0.0)
    wrapped = math.remainder(angle, 2 * math.pi)
    assert pitch == pytest.approx(wrapped, abs=1e-12) or abs(pitch) == pytest.approx(math.pi)
    assert pitch_rate == 5.0
    assert rpy(_about_y(angle), planar=True) == (0.0, pitch, 0.0)


def test_below_ninety_degrees_the_reading_is_the_3d_one_bit_for_bit() -> None:
    for degrees in np.linspace(-89.9, 89.9, 181):
        rot = _about_y(math.radians(degrees))
        assert euler_rates(rot, (0.0, 3.0, 0.0), planar=True) == euler_rates(rot, (0.0, 3.0, 0.0))
        assert rpy(rot, planar=True) == rpy(rot)


def test_a_3d_creature_keeps_its_euler_angles_past_ninety() -> None:
    roll, pitch, yaw, *_ = euler_rates(_about_y(math.radians(120)), (0.0, 5.0, 0.0))
    assert (abs(roll), math.degrees(pitch), abs(yaw)) == pytest.approx((math.pi, 60, math.pi))


@pytest.fixture(scope="module")
def tumbles(tmp_path_factory) -> dict:
    where = tmp_path_factory.mktemp("tumble")
    (where / "tumble.leg").write_text(TUMBLE)
    session = RunSession.from_file(where / "tumble.leg", generated=where / "generated")
    options = RunOptions(duration=0.9, fall_tilt=math.pi)
    backends = ["python"]
    from legdsl.sim.c_library import available

    if available() is None:
        backends.append("c")
    return {b: session.run("watch", [], options=options, backend=b).result for b in backends}


def test_a_tumble_is_followed_past_ninety_degrees_on_both_backends(tumbles: dict) -> None:
    for result in tumbles.values():
        traj = result.trajectory
        turned = traj.q[:, 2]  # the planar root's own pitch coordinate, never wrapped
        wrapped = np.remainder(turned + math.pi, 2 * math.pi) - math.pi
        assert float(turned[-1]) > math.radians(300)  # it turned most of a full turn
        assert np.allclose(traj.root_rpy[:, 1], wrapped, atol=1e-12)
        assert not traj.root_rpy[:, [0, 2]].any()
        # the table sees the pitch pass 100 degrees and still rising
        past = int(np.argmax(traj.state == 1))
        assert past > 0 and math.degrees(turned[past]) == pytest.approx(100, abs=2)
    if "c" in tumbles:
        python, c = tumbles["python"].trajectory, tumbles["c"].trajectory
        for name in ("t", "q", "v", "root_rpy", "state"):
            assert np.array_equal(getattr(python, name), getattr(c, name)), name
