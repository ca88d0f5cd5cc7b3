"""Notes on an ``ok`` run that visibly did not do what was asked (``legdsl.pipeline.run_notes``):
a controller stuck in one state, a speed command not followed, a path not followed."""

from __future__ import annotations

import io
import json
from pathlib import Path
from types import SimpleNamespace

import numpy as np
from conftest import CREATURES

from legdsl.pipeline.run_notes import run_notes
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions


def test_a_stuck_controller_and_an_unfollowed_command_are_told(
    generated: Path, tmp_path: Path
) -> None:
    """A trot whose thrust waits for a leg length the leg never reaches (its `full` too short
    for it, as a user's 20% longer legs were for the shipped 0.80 m) stood in UNLOADING from
    0.2 s to the end and said only "status ok"; it is told now, with the state, since when
    and the event the table waits for, in the log and in run.json."""
    log = io.StringIO()
    session = RunSession.from_file(CREATURES / "quadruped.leg", generated=generated, log=log)
    run = session.run("trot", ["speed=2m/s", "full=0.6m"], options=RunOptions(duration=5.0))
    assert run.status == "ok"
    told = log.getvalue()
    assert "legdsl: note: the controller sat in UNLOADING from 0.216 s to the end" in told
    assert "waiting for the event of its next row, FLIGHT's 'liftoff(active)'" in told
    assert "the speed command was 2.00 m/s and the forward speed 0.00 m/s" in told
    notes = json.loads((run.write(tmp_path / "stuck") / "run.json").read_text())["notes"]
    assert len(notes) == 2 and notes[0].startswith("the controller sat in UNLOADING")


def test_a_shipped_run_that_does_as_asked_gets_no_note(generated: Path, tmp_path: Path) -> None:
    log = io.StringIO()
    session = RunSession.from_file(CREATURES / "quadruped.leg", generated=generated, log=log)
    run = session.run("trot", ["speed=2m/s"], options=RunOptions(duration=5.0))
    assert run.status == "ok" and run_notes(run) == [] and "note" not in log.getvalue()
    assert "notes" not in json.loads((run.write(tmp_path / "trot") / "run.json").read_text())


class _Recording(SimpleNamespace):
    def __len__(self) -> int:
        return len(self.t)


def _run(speed: np.ndarray, command: np.ndarray, events: list[dict], **more: object) -> object:
    """A run's record for the notes: ``speed`` along x, ``command`` every 10 ms."""
    zero = np.zeros(len(speed))
    tr = _Recording(t=np.arange(len(speed)) * 0.01, speed_command=command,
                    com_vel=np.stack([speed, zero, zero], axis=1), root_rpy=np.zeros((len(speed), 3)))  # fmt: skip
    result = SimpleNamespace(status="ok", trajectory=tr, events=events, sim_time=float(tr.t[-1]))
    base = dict(result=result, time_unit=1.0, controller="c", path_reports=[],
                model=SimpleNamespace(controllers=[]))  # fmt: skip
    return SimpleNamespace(**(base | more))


def test_the_speed_note_wants_a_clear_miss_and_says_the_other_way() -> None:
    """A gallop told -3 m/s ran forwards at +1.2 m/s, "ok" and no word: a miss of more than a
    quarter of the command and 0.5 m/s is told, the other way said so; a near miss is not, and
    the window starts 3 s after the last change of the command."""
    n, states = 1001, [{"t": 0.1 * k, "kind": "state", "state": "A"} for k in range(100)]
    backwards = _run(np.full(n, 1.2), np.full(n, -3.0), states)
    (note,) = run_notes(backwards)
    assert (
        "-3.00 m/s and the forward speed 1.20 m/s (mean from 3 s to the end), the other way" in note
    )
    assert run_notes(_run(np.full(n, 2.3), np.full(n, 2.0), states)) == []  # 15% off: a trim
    changed = np.where(np.arange(n) < 800, 2.0, 0.0)  # a command at 8 s: 2 s since, no window
    assert run_notes(_run(np.full(n, 2.0), changed, states)) == []
    assert run_notes(_run(np.full(n, 2.0), np.full(n, np.nan), states)) == []  # no speed input


def test_a_command_near_the_largest_double_is_told_as_not_followed() -> None:
    """A speed command of 1e308 m/s overflowed the command's mean (numpy warned) and the run
    got no note, where 20 m/s got one: it is told, its number in a few figures."""
    import warnings

    n, states = 1001, [{"t": 0.1 * k, "kind": "state", "state": "A"} for k in range(100)]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        (note,) = run_notes(_run(np.full(n, 3.0), np.full(n, 1e308), states))
    assert note.startswith("the speed command was 1e+308 m/s and the forward speed 3.00 m/s")


def test_the_stuck_note_wants_a_long_share_of_the_run() -> None:
    n = 1001  # 10 s
    speed, command = np.zeros(n), np.full(n, np.nan)
    early = [{"t": 0.0, "kind": "state", "state": "A"}, {"t": 7.5, "kind": "state", "state": "B"}]
    (note,) = run_notes(_run(speed, command, early))  # 2.5 s, a quarter of the run
    assert note.startswith("the controller sat in B from 7.500 s to the end of the run (2.500 s")
    early[-1]["t"] = 8.5  # 1.5 s: a pause, not told
    assert run_notes(_run(speed, command, early)) == []
    early[-1]["t"] = 7.0
    late_switch = [*early, {"t": 9.0, "kind": "switch", "controller": "d"}]  # a takeover: moving
    assert run_notes(_run(speed, command, late_switch)) == []


def test_a_speed_still_rising_toward_the_command_is_told_to_run_longer() -> None:
    """A kangaroo told 5 m/s and run 3 s was still speeding up (2.86 m/s mean from 1.9 s, and
    rising) and the note said the controller "did not follow this command"; a 20 s run holds
    5.07 m/s. A speed changing toward the command at the end is told so, with the advice to
    run longer; a flat miss, or one drifting away, is still "did not follow"."""
    n, states = 601, [{"t": 0.1 * k, "kind": "state", "state": "A"} for k in range(60)]
    t = np.arange(n) * 0.01
    wobble = 0.4 * np.sin(2 * np.pi * t / 0.37)  # a hop's rise and fall within each stride
    rising = _run(0.6 * t + wobble, np.full(n, 5.0), states)
    (note,) = run_notes(rising)
    assert "still speeding up toward it at the end" in note and "run longer" in note
    assert "did not follow" not in note
    slowing = _run(6.0 - 0.6 * t + wobble, np.full(n, 1.0), states)
    assert "still slowing down toward it" in run_notes(slowing)[0]
    for speed in (np.full(n, 2.86) + wobble, 2.5 - 0.2 * t + wobble):  # flat, or drifting away
        (note,) = run_notes(_run(speed, np.full(n, 5.0), states))
        assert "did not follow this command" in note and "still" not in note


def test_a_turn_the_controller_does_not_follow_is_told_even_when_it_falls(generated: Path) -> None:
    """The quadruped's bound accepted turn_rate=17.2deg/s, turned the other way and fell at
    5.466 s with no word on the turn; the trot switching to the bound spun at 70 deg/s with a
    note on the speed only. Both are told now; a trot that turns as asked is told nothing."""
    log = io.StringIO()
    session = RunSession.from_file(CREATURES / "quadruped.leg", generated=generated, log=log)
    turn = ["speed=2.8m/s", "turn_rate=17.2deg/s"]
    fell = session.run("bound", turn, options=RunOptions(duration=10.0), backend="c")
    assert fell.status == "fell"
    told = log.getvalue()
    assert "the turn_rate command was 17.20 deg/s and the heading turned at -19" in told
    assert "(from 3 s to the fall), the other way" in told
    log.truncate(0)
    trot = session.run("trot", ["speed=2m/s", "turn_rate=17.2deg/s"], options=RunOptions(duration=8.0), backend="c")  # fmt: skip
    assert trot.status == "ok" and "turn_rate" not in log.getvalue()


def test_the_turn_note_wants_a_clear_miss_and_no_path() -> None:
    """Measured against the turn_rate of the controller running at the end, from SETTLE after
    its inputs last changed; none where a path steers it, or where it has no turn_rate."""

    def machine(rate: float, paths: tuple = ()) -> SimpleNamespace:
        return SimpleNamespace(input_names=("speed", "turn_rate"), inputs=[1.0, rate],
                               paths=list(paths), _history=[(0.0, [1.0, rate])])  # fmt: skip

    def run(yaw_rate: float, m: SimpleNamespace) -> object:
        r = _run(np.ones(800), np.full(800, np.nan), [], machine=m, scale=None)
        r.result.trajectory.root_rpy[:, 2] = np.angle(np.exp(1j * yaw_rate * r.result.trajectory.t))
        return r

    assert run_notes(run(0.31, machine(0.3))) == []
    spun = run_notes(run(1.2, machine(0.3)))
    assert len(spun) == 1 and "the turn_rate command was 17.19 deg/s" in spun[0]
    assert "heading turned at 68.75 deg/s (from 3 s to the end)" in spun[0]
    assert "the other way" in run_notes(run(-0.3, machine(0.3)))[0]
    assert run_notes(run(0.03, machine(0.0))) == []  # within TURN_MARGIN of 0
    assert run_notes(run(1.2, machine(0.3, (SimpleNamespace(shape="circle"),)))) == []
