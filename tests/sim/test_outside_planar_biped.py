"""The planar biped of Hodgins & Raibert (1990) written from the docs
(tests/good/outside/planar_biped.leg): a trunk, two telescoping legs on one hip point, and
Figure 4 with active and idle legs swapping at each liftoff. It holds 2 m/s (docs/biped.md,
"A planar biped (Hodgins & Raibert 1990)"). The somersault was not reached: see there."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from conftest import ROOT

from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions

LEG = ROOT / "tests" / "good" / "outside" / "planar_biped.leg"


def test_the_planar_biped_holds_2_m_s_without_falling(tmp_path: Path) -> None:
    sess = RunSession.from_file(LEG, generated=tmp_path)
    result = sess.run("run", ["speed=2m/s"], options=RunOptions(duration=7.0)).result
    assert result.status == "ok", result.message
    tr = result.trajectory
    late = tr.t >= 4.0  # the command ramps at 1 m/s^2 from standing
    mean = (tr.com[late][-1, 0] - tr.com[late][0, 0]) / (tr.t[late][-1] - tr.t[late][0])
    assert abs(mean - 2.0) < 0.1, mean
    assert tr.root_pos[:, 2].min() > 0.5


def test_the_planar_pitch_rate_servo_is_a_library_action(tmp_path: Path) -> None:
    """servo_pitch_rate (stdlib/raibert.leg) is the planar one-leg pitch-rate servo a
    somersault's last stance needs; the root's `pitch.value` reads past 90 deg."""
    text = LEG.read_text(encoding="utf-8") + (
        "controller spin {\n  table {\n"
        "    state A on liftoff(left): free_hip(left)\n"
        "    state B on pitch.value > 200 deg: servo_pitch_rate(left, trunk, 8 rad/s, 40 N*m*s/rad)\n"
        "  }\n}\n"
    )
    leg = tmp_path / "spin.leg"
    leg.write_text(text, encoding="utf-8")
    sess = RunSession.from_file(leg, generated=tmp_path / "gen")
    result = sess.run("spin", [], options=RunOptions(duration=0.05)).result
    assert result.status == "ok", result.message
    assert np.isfinite(result.trajectory.q).all()
