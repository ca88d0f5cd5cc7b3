"""A switch that never takes over is said in one line, on both backends: one given for after
``--time`` (its time never came), one the run ends before while it waits for a liftoff,
and one still waiting when the next comes due (the later takes over); a run whose switches were all made says
nothing. Two switches at one time are refused."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES, GENERATED

from legdsl.cli import main


def _needs_compiler() -> None:
    from legdsl.sim.c_library import available

    if available() is not None:
        pytest.skip(f"needs a C compiler: {available()}")


@pytest.mark.parametrize("backend", ["python", "c"])
def test_a_switch_after_the_end_is_said(
    backend: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    if backend == "c":
        _needs_compiler()
    argv = ["run", str(CREATURES / "hopper.leg"), "--controller", "hop", "--time", "0.2",
            "--generated", str(GENERATED), "--out", str(tmp_path / "run"), "--backend", backend,
            "--switch", "5s=hop", "--switch", "0.19s=hop"]  # fmt: skip
    assert main(argv) == 0
    err = capsys.readouterr().err
    # the hopper's wait: 1 s for a creature standing 0.81 m, sqrt(h / 0.81 m) as long for it
    assert (
        "legdsl: note: --switch 0.19s=hop was still waiting for a liftoff when the run ended "
        "at 0.2 s, and never took over (a switch waits up to 0.994 s for a liftoff); give a "
        "longer --time to see it"
    ) in err, err
    # one whose time never came did not wait for a liftoff: it is told as a late --set is
    assert (
        "legdsl: note: --switch 5s=hop comes after the run's end (0.2 s) and never took "
        "over; give a longer --time to see it"
    ) in err, err
    assert "5s=hop was still waiting" not in err, err
    argv[argv.index("--time") + 1] = "1.2"  # the handover comes by 1.05 s at the latest
    assert main([*argv[:-4], "--switch", "0.05s=hop"]) == 0
    assert "never took over" not in capsys.readouterr().err


# a controller with no liftoff event: it takes over on the first tick its switch is due
HOLD = """
controller hold {
  roles active = main
  table {
    state STAND on touchdown(active): free_hip(active)
  }
}
"""


def test_a_switch_still_waiting_when_the_next_is_due_gives_way(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Not two controller changes on one tick (the first a zero-length segment): the later
    switch takes over, on the first tick it is due, the same on both backends."""
    _needs_compiler()
    leg = tmp_path / "hopper.leg"
    leg.write_text((CREATURES / "hopper.leg").read_text() + HOLD)
    runs = {}
    for backend in ("python", "c"):
        out = tmp_path / backend
        argv = ["run", str(leg), "--controller", "hop", "--time", "0.4", "--backend", backend,
                "--generated", str(tmp_path / "gen"), "--out", str(out),
                "--switch", "0.19s=hop", "--switch", "0.25s=hold"]  # fmt: skip
        assert main(argv) == 0
        assert (
            "legdsl: note: --switch 0.19s=hop was still waiting for a liftoff when the switch "
            "to hold at 0.25 s came due, and never took over"
        ) in capsys.readouterr().err
        info = json.loads((out / "run.json").read_text())
        assert info["switches"][0]["superseded_by"] == {"t": 0.25, "controller": "hold"}
        assert [(s["controller"], s["from"], s["to"]) for s in info["segments"]] == [
            ("hop", 0.0, 0.25), ("hold", 0.25, 0.4),
        ]  # fmt: skip
        runs[backend] = np.load(out / "trajectory.npz")
    python, c = runs["python"], runs["c"]
    assert all(np.array_equal(python[k], c[k], equal_nan=True) for k in python.files)


def test_two_switches_at_one_time_are_refused(capsys: pytest.CaptureFixture[str]) -> None:
    argv = ["run", str(CREATURES / "hopper.leg"), "--controller", "hop", "--time", "1",
            "--switch", "0.5s=hop", "--switch", "500ms=hop"]  # fmt: skip
    assert main(argv) == 2
    assert (
        "--switch 0.5s=hop and --switch 0.5s=hop are at the same time: the run changes to one "
        "controller at a time; keep one"
    ) in capsys.readouterr().err


def test_a_scene_switch_that_never_took_over_is_a_note_at_its_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """As the note of a scene's late 'at T set' next to it: 'note:', the line's place and
    words (it read 'legdsl: the switch to hold at 5 s comes after ...', without either)."""
    leg = tmp_path / "hopper.leg"
    text = (CREATURES / "hopper.leg").read_text() + HOLD
    scene = (
        "scene late {\n  controller hop\n  at 5 s set speed = 0.5 m/s\n  at 5 s switch hold\n}\n"
    )
    leg.write_text(text + "\n" + scene)
    line = text.count("\n") + 5
    argv = ["run", str(leg), "--scene", "late", "--time", "0.2", "--backend", "python",
            "--generated", str(tmp_path / "gen"), "--out", str(tmp_path / "run")]  # fmt: skip
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert (
        f"legdsl: note: {leg}:{line - 1}:3: 'at 5 s set speed' of scene late comes after the run's "
        "end (0.2 s)"
    ) in err, err
    assert (
        f"legdsl: note: {leg}:{line}:3: 'at 5 s switch hold' of scene late comes after the "
        "run's end (0.2 s) and never took over; give a longer --time to see it"
    ) in err, err


def test_a_gait_tables_late_switch_is_named_by_the_line_that_chooses_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A scene's gait table switches where a command's band changes: a late one was told as
    '--switch 12s=gallop', an option nobody wrote; it is named by the scene's line now."""
    leg = CREATURES / "quadruped.leg"
    line = next(i for i, text in enumerate(leg.read_text().splitlines(), 1)
                if text.strip() == "at 12 s set speed = 4 m/s" and i > 540)  # fmt: skip
    argv = ["run", str(leg), "--scene", "by_speed", "--time", "0.1", "--backend", "python",
            "--generated", str(GENERATED), "--out", str(tmp_path / "run")]  # fmt: skip
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert "--switch 12s=gallop" not in err, err
    assert (
        f"legdsl: note: the switch to gallop that the gait table of scene by_speed chooses for "
        f"{leg}:{line}:3: 'at 12 s set speed' comes after the run's end (0.1 s) and never took "
        "over"
    ) in err, err


def test_a_switch_back_to_the_running_controller_past_a_superseded_one_says_it_restarts(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The kangaroo hopping, --switch 2.5s=jump still waiting when --switch 2.6s=hop came due:
    the hop's state machine restarted at 2.62 s, and only the jump's never taking over was
    said."""
    _needs_compiler()
    argv = ["run", str(CREATURES / "kangaroo.leg"), "--controller", "hop", "--time", "3",
            "--generated", str(GENERATED), "--out", str(tmp_path / "run"), "--backend", "c",
            "--switch", "2.5s=jump", "--switch", "2.6s=hop"]  # fmt: skip
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert (
        "came due, and never took over (a switch waits up to 0.643 s): give the later one a "
        "later time to see both; hop was still running, so --switch 2.6s=hop restarts its "
        "state machine"
    ) in err, err
