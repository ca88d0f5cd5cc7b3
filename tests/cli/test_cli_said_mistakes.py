"""What a user may get wrong in a run's options is said: two commands for one input at one
time are refused (on the command line, in the API and in a scene), a switch to the controller
already asked for is kept with a note (it restarts that controller's state machine)."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CREATURES, GENERATED

import legdsl
from legdsl.cli import main
from legdsl.lang.errors import UsageError
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions

HOPPER = CREATURES / "hopper.leg"


def _run(tmp_path: Path, *extra: str) -> list[str]:
    return ["run", str(HOPPER), "--controller", "hop", "--time", "0.2", "--backend", "python",
            "--generated", str(GENERATED), "--out", str(tmp_path / "run"), *extra]  # fmt: skip


def test_two_commands_for_one_input_at_one_time_are_refused_naming_both(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = _run(tmp_path, "--set", "speed=1m/s@0.1s", "--set", "speed=2m/s@100ms")
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert (
        "legdsl: --set speed=1m/s@0.1s and --set speed=2m/s@100ms command speed at the same "
        "time (0.1 s): an input takes one command at a time; keep one"
    ) in err, err
    assert not (tmp_path / "run").exists()
    session = RunSession.from_file(HOPPER, generated=GENERATED)
    with pytest.raises(UsageError, match="at the same time"):
        session.prepare("hop", ["speed=1m/s@0.1s", "speed=1m/s@0.1s"], options=RunOptions(0.2))
    # one input at two times, or two inputs at one time, are two commands
    assert main(_run(tmp_path, "--set", "speed=1m/s@0.1s", "--set", "speed=2m/s@0.15s")) == 0
    assert main(_run(tmp_path, "--set", "speed=1m/s@0.1s", "--set", "height=1.1m@0.1s")) == 0


def test_a_switch_to_the_controller_asked_for_is_kept_with_a_note(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(_run(tmp_path, "--switch", "0.05s=hop", "--backend", "python")) == 0
    err = capsys.readouterr().err
    assert (
        "legdsl: note: the switch to hop at 0.05 s is to the controller already asked for "
        "(since the start): it restarts hop's state machine at the next liftoff"
    ) in err, err
    assert main(_run(tmp_path)) == 0
    assert "note" not in capsys.readouterr().err


def test_a_drop_too_high_for_doubles_to_hold_the_creature_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from legdsl.pipeline.options import DROP_RESOLUTION

    # the hopper's shortest link, its thigh, is 0.3 m: doubles near H are up to H * 2^-52 apart
    highest = DROP_RESOLUTION * 0.3 / 2.0**-52
    session = RunSession.from_file(HOPPER, generated=GENERATED)
    plan = session.prepare("hop", options=RunOptions(0.2, drop=highest * 0.99), backend="python")
    assert plan.sim.q[plan.model.q_names.index("z")] > highest * 0.98
    with pytest.raises(UsageError, match=r"give --drop 1\.35e\+09m or less"):
        session.prepare("hop", options=RunOptions(0.2, drop=highest * 1.01), backend="python")
    assert main(_run(tmp_path, "--drop", "1e300")) == 2
    assert (
        "legdsl: --drop 1e+300m: doubles near that height are up to 2.22e+284 m apart, more than "
        "1e-06 of the creature's shortest link (thigh, 0.3 m), so its geometry would be lost in "
        "rounding; give --drop 1.35e+09m or less"
    ) in capsys.readouterr().err


def test_a_drop_whose_fall_outlasts_the_run_is_said_in_a_note(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(_run(tmp_path, "--drop", "30cm")) == 0  # 0.247 s at 9.81 m/s^2
    err = capsys.readouterr().err
    assert (
        "legdsl: note: --drop 0.3m: the fall alone takes 0.247 s, longer than the run (0.2 s), "
        "which ends with the creature in the air; give --time 0.247s or more, or a lower --drop"
    ) in err, err
    assert main(_run(tmp_path, "--drop", "10cm")) == 0
    assert "note" not in capsys.readouterr().err


def test_a_scenes_switch_to_the_controller_asked_for_is_kept_with_a_note(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "hopper.leg"
    path.write_text(
        HOPPER.read_text() + "scene again { controller hop; at 0.05 s switch hop; time 0.2 s }\n"
    )
    argv = ["run", str(path), "--scene", "again", "--backend", "python",
            "--generated", str(GENERATED), "--out", str(tmp_path / "run")]  # fmt: skip
    assert main(argv) == 0
    assert "note: the switch to hop at 0.05 s is to the controller already asked for" in (
        capsys.readouterr().err
    )


def test_the_command_line_overrides_a_scenes_line_at_the_same_time() -> None:
    """The scene's line cannot be left out from the command line, so a --set or --switch at
    its time replaces it (as an untimed --set replaces the scene's value), not 'keep one'."""
    from legdsl.pipeline.scenes import find_scene, scene_plan
    from legdsl.sim.run_loop import RunOptions

    session = RunSession.from_file(CREATURES / "biped.leg", generated=GENERATED)
    scene = find_scene(session.model, "run_gallop_run")
    _, sets, switches = scene_plan(scene, session.model, ["speed=2m/s@8000ms"], ["8s=run"])
    assert not any(s.startswith("speed=1.5") for s in sets)
    assert "speed=2m/s@8000ms" in sets and "speed=2.5m/s@16.0s" in sets
    assert switches == ["16.0s=run", "8s=run"]
    plan = session.prepare("run", sets, options=RunOptions(0.1), switches=switches)
    assert [(c.t, c.value) for c in plan.settings.schedule] == [(16.0, 2.5), (8.0, 2.0)]
    _, clashing, _ = scene_plan(scene, session.model, ["speed=2m/s@8s", "speed=3m/s@8s"], [])
    with pytest.raises(UsageError, match="at the same time"):  # two of the user's own still clash
        session.prepare("run", clashing, options=RunOptions(0.1), switches=switches)


def test_one_name_set_twice_on_the_command_line_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--set speed=1m/s --set speed=2m/s ran at 2 m/s without a word; a scene's value is still
    the command line's to override."""
    assert main(_run(tmp_path, "--set", "speed=1m/s", "--set", "speed = 2m/s")) == 2
    assert "--set speed=1m/s and --set speed = 2m/s both set speed: keep one" in (
        capsys.readouterr().err
    )
    sweep = ["sweep", str(HOPPER), "--controller", "hop", "--grid", "height=0.8m:1m:2",
             "--set", "speed=1m/s", "--set", "speed=2m/s", "--out", str(tmp_path / "sweep")]  # fmt: skip
    assert main(sweep) == 2
    assert "both set speed" in capsys.readouterr().err
    biped = ["run", str(CREATURES / "biped.leg"), "--scene", "run_gallop_run", "--time", "0.05",
             "--set", "speed=2.2m/s", "--generated", str(GENERATED), "--backend", "python",
             "--out", str(tmp_path / "biped")]  # fmt: skip
    assert main(biped) == 0


def test_a_value_and_a_command_at_0_s_for_one_name_are_refused_as_twice(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--set speed=1m/s --set speed=2m/s@0s ran at 2 m/s from the first tick, the first value
    never used, without a word; run(set=) merged 'speed' and 'speed ' (the later won)."""
    assert main(_run(tmp_path, "--set", "speed=2m/s@0ms", "--set", "speed=1m/s")) == 2
    assert ("--set speed=1m/s and --set speed=2m/s@0ms both set speed from the start (a command "
            "at 0 s replaces the value before it is used): keep one") in capsys.readouterr().err  # fmt: skip
    assert main(_run(tmp_path, "--set", "speed=1m/s", "--set", "speed=2m/s@0.1s")) == 0
    hopper = legdsl.load(HOPPER, generated=GENERATED)
    for given in ({"speed": "1 m/s", "speed ": "2 m/s"}, {"speed": "1 m/s", "speed@0s": "2 m/s"}):
        with pytest.raises(UsageError, match="both set speed"):
            hopper.run(controller="hop", set=given, time=0.05)


def test_a_fall_tilt_past_upside_down_is_refused_before_anything_is_compiled(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """docs/runtime.md: a run's options are refused before anything is compiled; a
    --fall-tilt past 180 deg was refused only after the creature's modules were written."""
    generated = tmp_path / "generated"
    argv = ["run", str(HOPPER), "--fall-tilt", "181", "--generated", str(generated)]
    assert main([*argv, "--out", str(tmp_path / "run")]) == 2
    assert "is past upside down (180 deg)" in capsys.readouterr().err
    assert not generated.exists() and not (tmp_path / "run").exists()


def test_a_pipe_whose_reader_stopped_is_told_as_such() -> None:
    """'-o /dev/stdout | head' said "Broken pipe (/dev/stdout); check the path and its
    permissions": neither was wrong."""
    import errno

    from legdsl.cli.common import os_refusal

    said = os_refusal(OSError(errno.EPIPE, "Broken pipe", "/dev/stdout"))
    assert said.startswith("/dev/stdout: the pipe's reader stopped reading"), said
    assert "permissions" not in said
