"""The flexing-spine quadruped whose stance hips servo the whole trunk's pitch
(tests/good/outside/spine_quadruped_posture.leg; docs/quadruped.md, "A quadruped with a
flexing spine"): spine_quadruped.leg's bound, which servoes the front half's pitch rate,
falls at 3 m/s (8.4 s); with the library's servo_pitch_rate_trunk (the two halves'
mass-weighted mean pitch rate) and its gains tuned, it bounds at 3 m/s."""

from __future__ import annotations

import numpy as np
from conftest import outside_session
from runtime_helpers import needs_c_compiler

from legdsl.sim.run_loop import RunOptions

pytestmark = needs_c_compiler


def test_the_bound_on_the_trunks_mean_pitch_holds_3_m_s() -> None:
    session = outside_session("spine_quadruped_posture.leg")
    opts = RunOptions(duration=6.0)
    run = session.run("bound", ["speed=3m/s"], options=opts, backend="c").result
    assert run.status == "ok", run.message
    tr = run.trajectory
    start = int(np.searchsorted(tr.t, 2.0))
    vx = (tr.com[-1, 0] - tr.com[start, 0]) / (tr.t[-1] - tr.t[start])
    assert abs(vx - 3.0) < 0.1 * 3.0, vx


def test_the_bound_on_the_front_halfs_pitch_falls_at_3_m_s() -> None:
    """What the trunk's servo mends: the shipped bound, servoing the root's (the front
    half's) pitch rate through the spine, falls nose down before 10 s."""
    session = outside_session("spine_quadruped.leg")
    opts = RunOptions(duration=10.0)
    run = session.run("bound", ["speed=3m/s"], options=opts, backend="c").result
    assert run.status != "ok"
    assert run.trajectory.root_rpy[-1, 1] > np.radians(45)
