"""A command given for a switch's time waits for the new controller to take over; one given
for a later time before that takes over is the latest, and the new controller starts with
it, not with the older one held for the switch (on both backends)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from conftest import CREATURES, GENERATED

from legdsl.cli import main


@pytest.mark.parametrize("backend", ["python", "c"])
def test_a_later_command_is_not_undone_by_the_switchs_own(backend: str, tmp_path: Path) -> None:
    if backend == "c":
        from legdsl.sim.c_library import available

        if available() is not None:
            pytest.skip(f"needs a C compiler: {available()}")
    out = tmp_path / "run"
    argv = ["run", str(CREATURES / "hopper.leg"), "--controller", "hop", "--time", "1.2",
            "--generated", str(GENERATED), "--out", str(out), "--backend", backend,
            "--switch", "0.05s=hop", "--set", "speed=1.5m/s@0.05s",
            "--set", "speed=0.5m/s@0.06s"]  # fmt: skip
    assert main(argv) == 0
    segments = json.loads((out / "run.json").read_text())["segments"]
    assert len(segments) == 2 and segments[1]["from"] > 0.06, segments
    assert segments[1]["inputs"]["speed"] == 0.5, segments


def _refusal(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    assert main(argv) == 2
    return capsys.readouterr().err.strip()


def test_a_switch_at_the_start_says_to_start_with_its_controller(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["run", str(CREATURES / "hopper.leg"), "--controller", "hop", "--switch", "0s=hop",
            "--generated", str(GENERATED), "--out", str(tmp_path / "run")]  # fmt: skip
    assert _refusal(argv, capsys) == (
        "legdsl: --switch 0s=hop: a switch comes after the start; to start with hop, write "
        "--controller hop, else give a time after 0, e.g. --switch 1s=hop"
    )


def test_a_switch_with_scale_says_what_to_run_instead(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Found by tests/sim/test_random_run_options.py: the scene's refusal gave the command,
    --switch's only 'the file legdsl scale writes'."""
    source = CREATURES / "hopper.leg"
    argv = ["run", str(source), "--controller", "hop", "--switch", "0.1s=hop", "--scale", "2",
            "--generated", str(GENERATED), "--out", str(tmp_path / "run")]  # fmt: skip
    assert _refusal(argv, capsys) == (
        f"legdsl: --switch with --scale is not supported: write the scaled file with 'legdsl "
        f"scale {source} --by 2 -o OUT.leg' and run it with --switch"
    )


def test_a_switch_that_leaves_a_path_says_the_new_controller_follows_none(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The biped's run on a circle, then the gallop, which has no path: it turned back to its
    default heading (0 deg) from wherever the circle left it, spun and fell, with no word.
    The run says so, and how to give the heading; not when the heading is commanded."""
    argv = ["run", str(CREATURES / "biped.leg"), "--controller", "run", "--time", "0.1",
            "--generated", str(GENERATED), "--out", str(tmp_path / "run"),
            "--path", "circle(center = (0, 5) m, radius = 5 m)", "--switch", "8s=gallop"]  # fmt: skip
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert "note: the switch to gallop at 8 s leaves run's path: gallop follows no path" in err
    assert "its heading is its default, 0 deg" in err and "--set heading=ANGLE@8s" in err
    assert main([*argv, "--set", "heading=170deg@8s"]) == 0
    err = capsys.readouterr().err
    assert "follows no path" in err and "its heading is its default" not in err
    assert main(argv[:-4]) == 0  # no switch, nothing to say
    assert "follows no path" not in capsys.readouterr().err
