"""Long work shows its progress with an estimate of the time left: a run, a video, a sweep."""

from __future__ import annotations

import itertools
import os
import pty
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest

from legdsl.pipeline.report import ProgressBar, progress_line, time_left

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


def test_the_first_bar_has_no_dangling_comma_and_long_times_are_in_hours_or_days(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """The first bar ended '0.00 / 600.00 s, ' (no estimate yet); a --time 1e9 run was 'about
    24722m22s left'."""
    progress_line(0.0, 600.0, "s", None)
    assert capsys.readouterr().err.endswith("  0.00 / 600.00 s\033[K")
    assert [time_left(s) for s in (75.0, 3599.9, 3600.0, 86399.0, 1483342.0)] == [
        "1m15s", "59m59s", "1h00m", "23h59m", "17d04h",
    ]  # fmt: skip
    progress_line(3038.4, 1e9, "s", 1483342.0)
    assert "about 17d04h left" in capsys.readouterr().err


def test_a_bar_stopped_short_ends_its_line(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """After a fall, a divergence or Ctrl-C the bar was left open, and the next message was
    printed on its line after a stale time left; a bar that said 'done' is left as it is."""
    clock = itertools.count(100.0, 2.0)
    monkeypatch.setattr(time, "perf_counter", lambda: next(clock))
    bar = ProgressBar()
    bar(0.0, 600.0)
    bar(0.47, 600.0)
    capsys.readouterr()
    bar.end()
    assert capsys.readouterr().err == f"\r[{'.' * 30}]   0.47 / 600.00 s, stopped\033[K\n"
    bar.end()  # once
    assert capsys.readouterr().err == ""
    done = ProgressBar()
    done(10.0, 10.0)
    capsys.readouterr()
    done.end()
    assert capsys.readouterr().err == ""


def _on_a_terminal(argv: list[str], both: bool = False) -> tuple[int, str]:
    """``legdsl ARGV``'s exit status and what it wrote to a pseudo-terminal as standard error
    (and ``both``: standard output too)."""
    leader, follower = pty.openpty()
    cmd = [sys.executable, "-m", "legdsl", *argv]
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    out = follower if both else subprocess.DEVNULL
    done = subprocess.run(cmd, cwd=ROOT, env=env, stdout=out, stderr=follower)
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
    return done.returncode, seen.decode()


def test_a_run_on_a_terminal_shows_the_time_left(generated: Path) -> None:
    """The bar is drawn only on a terminal: here a pseudo-terminal as standard error."""
    status, text = _on_a_terminal(
        ["run", "creatures/hopper.leg", "--controller", "hop", "--backend", "python",
         "--time", "10", "--generated", str(generated),
         "--out", str(generated.parent / "progress-run")]
    )  # fmt: skip
    assert status == 0
    assert "left" in text and text.rstrip().endswith("done")


def test_a_run_that_falls_ends_its_bar_before_the_summary(generated: Path) -> None:
    """The summary's first row was printed on the bar's line, after 'about 0m46s left'."""
    status, text = _on_a_terminal(
        ["run", "creatures/hopper.leg", "--controller", "hop", "--backend", "python",
         "--fall-tilt", "5deg", "--time", "600", "--generated", str(generated),
         "--out", str(generated.parent / "progress-fall")], both=True
    )  # fmt: skip
    assert status != 0 and "fell" in text
    assert re.search(r"/ 600\.00 s, stopped\x1b\[K\r?\n  creature ", text), text
