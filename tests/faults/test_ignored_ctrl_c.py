"""Ctrl-C (SIGINT) ignored when legdsl started stays ignored, as the ending signals do: a
``legdsl run ... &`` from a non-interactive shell script starts so. It was ignored while the
creature compiled, then taken over for the simulation: a SIGINT stopped the run (exit 130)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import legdsl
from legdsl.signals import handled
from tests.faults.processes import wait_until_simulating

ROOT = Path(__file__).resolve().parents[2]
HOPPER = str(ROOT / "creatures" / "hopper.leg")
SRC = str(Path(legdsl.__file__).resolve().parents[1])  # the legdsl this test imported


def _ignores(pid: int, sig: int) -> bool:
    """Whether ``sig`` is ignored in process ``pid`` (Linux's /proc/PID/status, SigIgn)."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("SigIgn:"):
            return bool(int(line.split()[1], 16) >> (sig - 1) & 1)
    raise AssertionError("no SigIgn line")


def test_handled_leaves_an_ignored_ctrl_c_ignored() -> None:
    before = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        with handled((signal.SIGINT, signal.SIGTERM), lambda signum, frame: None):
            assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGINT, before)


def test_a_run_started_with_ctrl_c_ignored_ignores_it_while_simulating(
    generated: Path, tmp_path: Path
) -> None:
    out = tmp_path / "run"
    argv = [sys.executable, "-m", "legdsl", "run", HOPPER, "--controller", "hop",
            "--time", "1e9", "--record-rate", "10Hz", "--backend", "python",
            "--generated", str(generated), "--out", str(out)]  # fmt: skip
    proc = subprocess.Popen(argv, cwd=tmp_path, env=dict(os.environ, PYTHONPATH=SRC),
                            text=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN))  # fmt: skip
    try:
        wait_until_simulating(proc)
        assert _ignores(proc.pid, signal.SIGINT)
        proc.send_signal(signal.SIGINT)
        time.sleep(1.0)
        assert proc.poll() is None, proc.communicate()
        assert _ignores(proc.pid, signal.SIGINT)
        proc.send_signal(signal.SIGTERM)  # what ends it
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    assert proc.returncode == 128 + signal.SIGTERM, err
    run = json.loads((out / "run.json").read_text())
    assert run["status"] == "interrupted" and run["cause"] == "SIGTERM", run
