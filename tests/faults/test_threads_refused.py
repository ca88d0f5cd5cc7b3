"""A thread the system will not start ("can't start new thread", under ``ulimit -v``): a sweep
waited for ever, its process pool's manager thread dead; a batch of runs was an internal error.
Each is now one line, and a sweep keeps what it did."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import CREATURES

import legdsl.cli as cli
from legdsl.cli.process import THREAD_REFUSED

_SWEEP = """
import multiprocessing.queues, sys
def refused(self): raise RuntimeError("can't start new thread")
multiprocessing.queues.Queue._start_thread = refused  # the pool's feeder thread, started
from legdsl.cli import main                           # by its manager thread
sys.exit(main(sys.argv[1:]))
"""


def test_a_sweep_whose_pool_cannot_start_a_thread_ends(tmp_path: Path) -> None:
    out = tmp_path / "sweep"
    proc = subprocess.run(
        [sys.executable, "-c", _SWEEP, "sweep", str(CREATURES / "hopper.leg"),
         "--controller", "hop", "--grid", "speed=0.5:1:2", "--time", "0.2", "--from", "0.1",
         "--jobs", "2", "--out", str(out)],
        capture_output=True, text=True, timeout=90, cwd=tmp_path,
        env={**os.environ, "PYTHONPATH": str(Path(__file__).parents[2] / "src")},
    )  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stderr and "Exception in thread" not in proc.stderr
    assert "a thread could not start" in proc.stderr.splitlines()[-1]
    assert "the same command again goes on" in proc.stderr


def test_a_command_whose_thread_cannot_start_says_so(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    def refused(*_: object) -> object:
        raise RuntimeError("can't start new thread")

    monkeypatch.setattr(cli, "_cmd_show", refused)
    assert cli.main(["show", str(CREATURES / "hopper.leg")]) == 2
    assert capsys.readouterr().err == f"legdsl: {THREAD_REFUSED}\n"
