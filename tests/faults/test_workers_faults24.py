"""Faults of the fault hunt of the newest features (faults24): the workers of a tune or sweep
killed by SIGKILL."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

from legdsl.api.sweep_cli import writer_lock

_SCRIPT = """
import sys, time
from pathlib import Path
from legdsl.api.sweep_cli import writer_lock
from legdsl.api.workers import Workers

lock = writer_lock(Path(sys.argv[1]), "tune")  # as legdsl tune holds it while it runs
with Workers(2) as pool:
    list(pool.as_completed(abs, [1, 2]))
    print(*pool._pool._processes, flush=True)
    time.sleep(60)
"""


def _gone(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (FileNotFoundError, ProcessLookupError):
        return True
    return state in ("Z", "X")  # ended, whether or not its new parent has reaped it yet


def test_workers_end_with_a_killed_parent_and_free_the_lock(tmp_path: Path) -> None:
    """A tune killed by SIGKILL (kill -9, the out-of-memory killer) left its forked workers
    waiting for work forever, holding the inherited OUT/.tune.lock: every later tune into that
    --out was refused, 'another legdsl tune is writing', by nothing that would ever finish."""
    parent = subprocess.Popen(
        [sys.executable, "-c", _SCRIPT, str(tmp_path)],
        stdout=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONPATH": str(Path(__file__).parents[2] / "src")},
    )
    assert parent.stdout is not None
    pids = [int(p) for p in parent.stdout.readline().split()]
    assert len(pids) == 2
    parent.send_signal(signal.SIGKILL)
    parent.wait()
    deadline = time.monotonic() + 5
    while not all(_gone(p) for p in pids) and time.monotonic() < deadline:
        time.sleep(0.05)
    survivors = [p for p in pids if not _gone(p)]
    for p in survivors:  # never leave them behind, whatever the outcome
        os.kill(p, signal.SIGKILL)
    assert not survivors, "the workers outlived their killed parent"
    writer_lock(tmp_path, "tune").close()  # the next tune is not refused
