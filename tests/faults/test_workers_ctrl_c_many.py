"""Ctrl-C in a sweep of very many runs: 'sweep interrupted', 'interrupted', then the process
never ended (an outside user's sweep of 1,000,000 runs, 2 of 3 tries). Every run's future was
submitted at once, and each wait for the next result took the lock of every pending future,
one after the other: the KeyboardInterrupt nearly always landed in there, leaving a future's
lock taken, which the executor's thread then waited for, and Python's exit for that thread."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

_SCRIPT = """
import sys, time
from legdsl.api.workers import Workers

def nap(x):
    time.sleep(0.001)
    return x

try:
    with Workers(1) as pool:
        for k, _ in enumerate(pool.as_completed(nap, range(200_000))):
            if k == 50:
                print("running", flush=True)
except KeyboardInterrupt:
    print("stopped", flush=True)
    sys.exit(130)
"""


@pytest.mark.parametrize("delay", [0.2, 0.9, 1.7])
def test_ctrl_c_in_a_pool_of_very_many_items_ends_the_process(delay: float) -> None:
    proc = subprocess.Popen(
        [sys.executable, "-c", _SCRIPT],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONPATH": str(Path(__file__).parents[2] / "src")},
    )
    try:
        assert proc.stdout is not None
        started = time.monotonic()
        line = proc.stdout.readline()
        assert line.strip() == "running", (line, proc.stderr.read() if proc.stderr else "")
        assert time.monotonic() - started < 20, "the first results took long to come"
        time.sleep(delay)
        proc.send_signal(signal.SIGINT)
        try:
            out, err = proc.communicate(timeout=20)
        except subprocess.TimeoutExpired:
            pytest.fail("still running 20 s after Ctrl-C")
        assert proc.returncode == 130, err
        assert out.strip() == "stopped"
        assert "Traceback" not in err, err
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
