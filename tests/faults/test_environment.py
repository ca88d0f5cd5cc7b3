"""The world around a command: its standard output read by ``head`` (a reader that leaves)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from legdsl.cli.process import QuietWhenClosed

ROOT = Path(__file__).resolve().parents[2]
HOPPER = str(ROOT / "creatures" / "hopper.leg")


@pytest.mark.parametrize("unbuffered", ["", "1"])
def test_a_run_whose_reader_left_still_writes_everything(
    generated: Path, tmp_path: Path, unbuffered: str
) -> None:
    """``legdsl run ... --animate | head -1``: the run, its player and its exit status are
    those of a run nobody read; no "Broken pipe" (it was exit 2 before the player)."""
    out = tmp_path / "run"
    argv = [sys.executable, "-m", "legdsl", "run", HOPPER, "--time", "0.1", "--animate",
            "--generated", str(generated), "--out", str(out)]  # fmt: skip
    env = {**os.environ, "PYTHONUNBUFFERED": unbuffered}
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env)
    assert proc.stdout is not None and proc.stderr is not None
    proc.stdout.close()  # the reader leaves before the first line
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=300) == 0, err
    assert "Broken pipe" not in err and "Traceback" not in err, err
    assert {p.name for p in out.iterdir()} >= {"run.json", "trajectory.npz", "animation.html"}


def test_the_quiet_stdout_passes_text_on_until_the_reader_leaves() -> None:
    class Pipe:
        def __init__(self) -> None:
            self.text, self.closed_at = "", 2

        def write(self, text: str) -> int:
            if len(self.text.splitlines()) >= self.closed_at:
                raise BrokenPipeError(32, "Broken pipe")
            self.text += text
            return len(text)

        def flush(self) -> None:
            pass

        def fileno(self) -> int:
            raise ValueError("no descriptor")  # a stream without one: nothing to redirect

    pipe = Pipe()
    quiet = QuietWhenClosed(pipe)  # type: ignore[arg-type]
    for line in ("a\n", "b\n", "c\n", "d\n"):
        assert quiet.write(line) == 2
    quiet.flush()
    assert pipe.text == "a\nb\n" and quiet.reader_left
