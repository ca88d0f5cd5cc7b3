"""A planar quadruped written from the docs (tests/good/outside/planar_quadruped.leg): the
shipped quadruped's trunk and legs in the sagittal plane, two telescoping legs on each of
a front and a rear hip point (four feet). `bound` runs the front and rear pairs as a
virtual biped, `pronk` lands all four together; both hold 0.5 to 2 m/s for 10 s
(docs/quadruped.md, "A planar quadruped")."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import OUTSIDE, outside_session

from legdsl.sim.run_loop import RunOptions

LEG = OUTSIDE / "planar_quadruped.leg"


def _mean_speed(t: np.ndarray, com: np.ndarray, start: float) -> float:
    late = t >= start
    return float((com[late][-1, 0] - com[late][0, 0]) / (t[late][-1] - t[late][0]))


@pytest.mark.parametrize(
    ("controller", "speed", "tolerance"),
    [("bound", 0.5, 0.06), ("bound", 2.0, 0.06), ("pronk", 0.5, 0.04), ("pronk", 2.0, 0.04)],
)
def test_the_planar_quadruped_holds_its_speed_for_10_s(
    controller: str, speed: float, tolerance: float
) -> None:
    sess = outside_session(LEG.name)
    result = sess.run(controller, [f"speed={speed}m/s"], options=RunOptions(duration=10.0)).result
    assert result.status == "ok", result.message
    tr = result.trajectory
    mean = _mean_speed(tr.t, tr.com, 3.0)
    assert abs(mean - speed) < tolerance * speed, mean  # measured: +2.7, -3.4, +2.0, -1.1%
    late = tr.t >= 3.0
    down = tr.contact[late].astype(bool)
    assert (down[:, 0] == down[:, 1]).all() and (down[:, 2] == down[:, 3]).all()  # pairs as one
    front, rear = down[:, 0], down[:, 2]
    t = tr.t[late][1:]
    front_td, rear_td = t[front[1:] & ~front[:-1]], t[rear[1:] & ~rear[:-1]]
    gap = np.median([np.abs(rear_td - x).min() for x in front_td])  # to the nearest rear touchdown
    both = (front & rear).sum() / (front | rear).sum()
    if controller == "bound":  # the pairs take turns (measured: gap 0.122, 0.083 s; both 4, 19%)
        assert gap > 0.06 and both < 0.25, (gap, both)
    else:  # all four land together (measured: 5 ms; both ends down 82, 54% of the stance)
        assert gap < 0.015 and both > 0.45, (gap, both)


def test_the_pronk_takes_over_from_the_bound_and_back() -> None:
    """`--switch 5s=pronk --switch 10s=bound` at 1.5 m/s: the pronk starts its stroke and speed
    trims afresh (`own`); with the bound's it fell 0.9 s after the switch."""
    sess = outside_session(LEG.name)
    options = RunOptions(duration=15.0)
    run = sess.run("bound", ["speed=1.5m/s"], switches=["5s=pronk", "10s=bound"], options=options)
    assert run.result.status == "ok", run.result.message


def test_table_2_pairs_a_planar_quadruped_front_and_rear(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """`--table2 "quadruped bound"` found its pairs from the hips' left and right, which a
    planar quadruped has not ("the front/rear pairs need ... two left and two right")."""
    from legdsl.cli import main

    run = tmp_path / "run"
    argv = ["run", str(LEG), "--controller", "bound", "--set", "speed=1.5m/s", "--time", "5"]
    assert main([*argv, "--generated", str(tmp_path / "g"), "--out", str(run)]) == 0
    capsys.readouterr()
    table = ["metrics", str(run), "--from", "2", "--table2", "quadruped bound"]
    assert main(table) == 0
    found = capsys.readouterr().out
    assert main([*table, "--group", "front=fl,fr", "--group", "rear=rl,rr"]) == 0
    assert "gathered flight phase duration" in found and found == capsys.readouterr().out
