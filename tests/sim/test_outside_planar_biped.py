"""The planar biped of Hodgins & Raibert (1990) written from the docs
(tests/good/outside/planar_biped.leg): a trunk, two telescoping legs on one hip point, and
Figure 4 with active and idle legs swapping at each liftoff. Its tuned `run` holds 2 m/s
within 3%, and `flip` turns a front somersault out of the run and runs on (docs/biped.md,
"A planar biped (Hodgins & Raibert 1990)")."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from conftest import OUTSIDE, outside_session

from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions

LEG = OUTSIDE / "planar_biped.leg"


def test_the_planar_biped_holds_2_m_s_without_falling() -> None:
    sess = outside_session(LEG.name)
    result = sess.run("run", ["speed=2m/s"], options=RunOptions(duration=7.0)).result
    assert result.status == "ok", result.message
    tr = result.trajectory
    late = tr.t >= 4.0  # the command ramps at about 1 m/s^2 from standing
    mean = (tr.com[late][-1, 0] - tr.com[late][0, 0]) / (tr.t[late][-1] - tr.t[late][0])
    assert abs(mean - 2.0) < 0.06, mean  # the tuned gains: within 3%
    assert tr.root_pos[:, 2].min() > 0.5
    # both legs run: each stance of either leg lasts (no 5 ms scuffs of the right foot,
    # as before the new active leg was kept short while the body still rises)
    for leg in range(2):
        down = tr.contact[late][:, leg].astype(int)
        starts = np.flatnonzero(np.diff(down) == 1)
        ends = np.flatnonzero(np.diff(down) == -1)
        assert len(starts) >= 2, leg
        stances = [tr.t[late][e] - tr.t[late][s] for s in starts for e in ends[ends > s][:1]]
        assert min(stances) > 0.1, (leg, stances)


def _trunk_lowest(z: np.ndarray, pitch: np.ndarray) -> np.ndarray:
    """The lowest corner of the trunk's 0.5 m x 0.2 m box (it has no contact points)."""
    return z - (0.25 * np.abs(np.sin(pitch)) + 0.1 * np.abs(np.cos(pitch)))


def test_the_planar_biped_flips_once_and_runs_on() -> None:
    """`flip` at 2 m/s: the first stance after flip_at (6 s) spins the trunk up, one flight
    carries it round, it lands on a foot at a full turn (pitch.value + 2 pi +- 30 deg from
    that stance's touchdown) and runs on at 2 m/s for the 4 s left, the trunk never down."""
    sess = outside_session(LEG.name)
    options = RunOptions(duration=11.0, fall_tilt=math.pi)
    result = sess.run("flip", ["speed=2m/s"], options=options).result
    assert result.status == "ok", result.message
    tr = result.trajectory
    pitch = tr.q[:, list(tr.q_names).index("pitch")]  # pitch.value: turns unwrapped
    down = tr.contact.any(axis=1)
    k = np.arange(len(tr.t))
    takeoff_td = k[(tr.t > 6.0) & down & ~np.roll(down, 1)][0]
    liftoff = k[(k > takeoff_td) & ~down][0]
    landing = k[(k > liftoff) & down][0]
    turned = math.degrees(pitch[landing] - pitch[takeoff_td])
    assert abs(turned - 360.0) < 30.0, turned
    assert math.degrees(pitch[landing] - pitch[liftoff]) > 270.0  # most of it in the flight
    assert tr.t[landing] - tr.t[liftoff] < 0.8  # one flight
    assert _trunk_lowest(tr.root_pos[:, 2], pitch).min() > 0.2
    after = tr.t >= tr.t[landing] + 1.0
    assert tr.t[-1] - tr.t[landing] > 3.0
    mean = (tr.com[after][-1, 0] - tr.com[after][0, 0]) / (tr.t[after][-1] - tr.t[after][0])
    assert abs(mean - 2.0) < 0.1, mean
    assert np.abs(np.degrees(pitch[after] - pitch[takeoff_td - 1]) - 360.0).max() < 30.0
    assert tr.contact[after].any(axis=0).all()  # both feet keep landing


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
