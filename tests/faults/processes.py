"""Waiting for a ``legdsl run`` in a subprocess to be simulating before a signal is sent to it.

Its start (imports, loading and byte-compiling the generated modules) takes some 1.2 s of
processor time on the test machine; a signal before the run loop ends the command with nothing
recorded, which is right, but not what a test of a run's ending asks for. Processor time, not
wall time, so that a machine busy with other tests cannot make the signal come early.
"""

from __future__ import annotations

import os
import subprocess
import time
from pathlib import Path

SIMULATING_AFTER = 3.0  # processor seconds: the start's 1.2 s and room to spare


def cpu_seconds(pid: int) -> float | None:
    """The processor time a process has used so far (Linux's /proc), or None elsewhere."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return None
    return (int(stat[11]) + int(stat[12])) / os.sysconf("SC_CLK_TCK")


def wait_until_simulating(proc: subprocess.Popen[str], after: float = SIMULATING_AFTER) -> None:
    """Until ``proc`` has used ``after`` seconds of processor time (or slept them, where that
    cannot be read); it must still be running then."""
    deadline = time.monotonic() + 120
    while proc.poll() is None and time.monotonic() < deadline:
        used = cpu_seconds(proc.pid)
        if used is None:
            time.sleep(after)
            break
        if used >= after:
            break
        time.sleep(0.05)
    assert proc.poll() is None, proc.communicate()
