"""Long work shows its progress with an estimate of the time left: a run, a video, a sweep."""

from __future__ import annotations

import os
import pty
import subprocess
import sys
import time
from pathlib import Path

import pytest

from legdsl.pipeline.report import ProgressBar, progress_line

ROOT = Path(__file__).resolve().parents[2]


def test_the_bar_estimates_the_time_left_from_the_pace(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    clock = iter([100.0, 102.0, 104.0])  # 2 s of wall time for each simulated second
    monkeypatch.setattr(time, "perf_counter", lambda: next(clock))
    bar = ProgressBar()
    bar(1.0, 10.0)
    assert "left" not in capsys.readouterr().err  # no pace yet
    bar(2.0, 10.0)
    assert "2.00 / 10.00 s, about 0m16s left" in capsys.readouterr().err  # 8 s to go at 2 s/s
    bar(10.0, 10.0)
    line = capsys.readouterr().err
    assert line.endswith("done\n") and "#" * 30 in line


def test_a_sweeps_bar_counts_runs(capsys: pytest.CaptureFixture[str]) -> None:
    progress_line(3, 12, "runs", 75.0)
    assert "[#######.......................] 3/12 runs, about 1m15s left" in capsys.readouterr().err


def test_a_run_on_a_terminal_shows_the_time_left(generated: Path) -> None:
    """The bar is drawn only on a terminal: here a pseudo-terminal as standard error."""
    leader, follower = pty.openpty()
    cmd = [sys.executable, "-m", "legdsl", "run", "creatures/hopper.leg", "--controller", "hop",
           "--backend", "python", "--time", "10", "--generated", str(generated),
           "--out", str(generated.parent / "progress-run")]  # fmt: skip
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    done = subprocess.run(cmd, cwd=ROOT, env=env, stdout=subprocess.DEVNULL, stderr=follower)
    os.close(follower)
    seen = b""
    while True:
        try:
            chunk = os.read(leader, 65536)
        except OSError:  # the terminal's other end is closed and drained
            break
        if not chunk:
            break
        seen += chunk
    os.close(leader)
    assert done.returncode == 0
    text = seen.decode()
    assert "left" in text and text.rstrip().endswith("done")
