"""What a user may get wrong in a run's options is said: two commands for one input at one
time are refused (on the command line, in the API and in a scene), a switch to the controller
already asked for is kept with a note (it restarts that controller's state machine)."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CREATURES, GENERATED

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
