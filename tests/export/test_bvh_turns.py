"""BVH channels of joints that turn past half a turn stay continuous (no 360-degree jumps)."""

from __future__ import annotations

import math
from pathlib import Path

import bvh
import numpy as np
import pytest
from standin import ModelKinematics

from legdsl.check.source import check_model
from legdsl.export.bvh import bvh_text
from legdsl.export.motion import motion_from
from legdsl.sim.trajectory import empty

SPINNER = """
creature spinner {
  planar
  body trunk free {
    mass 2 kg  inertia 0.1 kg*m^2
    initial x = 0 m, z = 0.6 m, pitch = 0 deg
  }
  body arm on trunk via revolute hip at (0.1 m, 0 m) {
    length 0.5 m  com 0.25 m  mass 0.5 kg  inertia 0.01 kg*m^2
  }
}
"""


def test_angles_that_pass_half_a_turn_keep_turning(tmp_path: Path) -> None:
    source = tmp_path / "spinner.leg"
    source.write_text(SPINNER)
    model = check_model(source)
    times = np.linspace(0.0, 1.0, 101)
    tr = empty(
        len(times), 4, 4, 0, 0, q_names=model.q_names, v_names=model.v_names,
        contact_names=(), state_names=(), total_mass=model.total_mass,
    )  # fmt: skip
    tr.t[:] = times
    # the trunk tumbles two turns forward (14.4 degrees a frame), the arm one turn back on it
    tr.q[:] = np.column_stack(
        [0 * times, 0.6 + 0 * times, 4 * math.pi * times, -2 * math.pi * times]
    )
    motion = motion_from(model, tr, ModelKinematics(model), fps=50)
    mocap = bvh.Bvh(bvh_text(motion))
    for name in ("trunk", "arm"):
        channels = [c for c in mocap.joint_channels(name) if c.endswith("rotation")]
        angles = np.array(
            [mocap.frame_joint_channels(f, name, channels) for f in range(mocap.nframes)]
        )
        steps = np.abs(np.diff(angles, axis=0)).max()
        assert steps < 20.0, f"{name}'s channels jump {steps:.1f} deg between frames"
    # legdsl's pitch about +y is a turn about BVH's -z: the trunk ends at -720 degrees, the arm
    # (relative to it) at +360, as the coordinates say
    last = mocap.nframes - 1
    trunk = mocap.frame_joint_channels(last, "trunk", ["Zrotation"])[0]
    assert trunk == pytest.approx(-720.0, abs=1e-4)
    arm = mocap.frame_joint_channels(last, "arm", ["Zrotation"])[0]
    assert arm == pytest.approx(360.0, abs=1e-4)
