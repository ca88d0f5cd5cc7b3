"""Commands with worker processes under Ctrl-C and SIGTERM: ``tune`` writes the best it has
found so far, ``sweep`` keeps its finished rows, and no worker is left running."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


ENV = dict(os.environ, PYTHONPATH=str(ROOT / "src"), PYTHONUNBUFFERED="1")


def _start(argv: list[str]) -> subprocess.Popen[str]:
    """``legdsl ARGV`` in a session of its own (its workers in its process group)."""
    return subprocess.Popen([sys.executable, "-m", "legdsl", *argv], cwd=ROOT, env=ENV,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            start_new_session=True)  # fmt: skip


def _stop(proc: subprocess.Popen[str], sig: int, whole_group: bool) -> str:
    """Send ``sig`` to the whole process group, as a terminal's Ctrl-C does, or to the command
    alone, as ``kill`` does; its output once it has ended, with no worker left behind."""
    assert proc.poll() is None, proc.communicate()
    if whole_group:
        os.killpg(proc.pid, sig)
    else:
        proc.send_signal(sig)
    output, _ = proc.communicate(timeout=120)
    # nobody left in its process group: a worker the command stopped may take a moment to be
    # gone on a loaded machine, one left waiting for work never is
    deadline = time.monotonic() + 10
    with pytest.raises(ProcessLookupError):
        while time.monotonic() < deadline:
            os.killpg(proc.pid, 0)
            time.sleep(0.05)
    return output


@pytest.mark.parametrize(
    ("sig", "whole_group", "code", "ended"),
    [(signal.SIGINT, True, 130, "interrupted"), (signal.SIGTERM, False, 143, "terminated"),
     (signal.SIGHUP, False, 129, "terminated")],
    ids=["ctrl-c", "sigterm", "sighup"],
)  # fmt: skip
def test_a_stopped_tune_writes_the_best_so_far(
    generated: Path, tmp_path: Path, sig: int, whole_group: bool, code: int, ended: str
) -> None:
    out = tmp_path / "tuned"
    argv = ["tune", "creatures/hopper.leg", "--controller", "hop", "--param", "k_speed=0.02:0.2",
            "--speeds", "1m/s", "--time", "3", "--from", "1", "--generations", "1000",
            "--popsize", "4", "--jobs", "2", "--out", str(out), "--generated", str(generated)]  # fmt: skip
    proc = _start(argv)
    assert proc.stdout is not None
    seen = ""
    while not seen.startswith("generation 2/") and proc.poll() is None:
        seen = proc.stdout.readline()
    output = _stop(proc, sig, whole_group)
    assert proc.returncode == code, output
    assert "Traceback" not in output and "internal error" not in output, output
    result = json.loads((out / "tune.json").read_text())
    assert result["ended"] == ended
    if sig != signal.SIGINT:  # a closed terminal was told as a SIGTERM
        assert (
            f"terminated ({signal.Signals(sig).name})" in output
            and result["signal"] == signal.Signals(sig).name
        )
    assert 2 <= len(result["history"]) < 1000
    assert result["best"]["objective"] <= result["start"]["objective"]
    assert f"the best of {len(result['history'])} generations so far" in output
    assert "k_speed" in (out / "hopper.leg").read_text()
    assert (out / "tune.png").stat().st_size > 5_000


def test_a_terminated_sweep_keeps_its_rows_and_stops_its_workers(
    generated: Path, tmp_path: Path
) -> None:
    out = tmp_path / "sweep"
    argv = ["sweep", "creatures/hopper.leg", "--controller", "hop", "--grid",
            "speed=0.5:1.5:2000", "--time", "3", "--from", "1", "--jobs", "2", "--out", str(out),
            "--generated", str(generated)]  # fmt: skip
    proc = _start(argv)
    table = out / "sweep.csv"
    while proc.poll() is None and (not table.is_file() or table.read_text().count("\n") < 3):
        time.sleep(0.05)  # the sweep prints nothing until its end: wait for its first rows
    output = _stop(proc, signal.SIGTERM, whole_group=False)
    assert proc.returncode == 143, output
    assert "terminated (SIGTERM)" in output and "Traceback" not in output
    assert 3 <= table.read_text().count("\n") < 2001


def test_a_stopped_tune_run_again_goes_on_as_if_it_had_never_stopped(
    generated: Path, tmp_path: Path
) -> None:
    """The journal's generations are told to a fresh CMA-ES without runs: the resumed tune's
    results equal, byte for byte, those of a tune that was never stopped."""
    argv = ["tune", "creatures/hopper.leg", "--controller", "hop", "--param", "k_speed=0.02:0.2",
            "--param", "kp=50:300", "--speeds", "1m/s,1.5m/s", "--time", "2", "--from", "0.5",
            "--generations", "6", "--popsize", "4", "--seed", "3", "--jobs", "2",
            "--generated", str(generated)]  # fmt: skip
    whole, stopped = tmp_path / "whole", tmp_path / "stopped"
    proc = _start([*argv, "--out", str(stopped)])
    assert proc.stdout is not None
    seen = ""
    while not seen.startswith("generation 2/") and proc.poll() is None:
        seen = proc.stdout.readline()
    _stop(proc, signal.SIGINT, whole_group=True)
    assert proc.returncode == 130
    assert len(json.loads((stopped / "tune.json").read_text())["history"]) < 6
    assert (stopped / ".tune-journal.json").is_file()
    again = subprocess.run([sys.executable, "-m", "legdsl", *argv, "--out", str(stopped)],
                           cwd=ROOT, env=ENV, capture_output=True, text=True, check=True)  # fmt: skip
    assert "from before" in again.stdout
    subprocess.run([sys.executable, "-m", "legdsl", *argv, "--out", str(whole)], cwd=ROOT,
                   env=ENV, capture_output=True, check=True)  # fmt: skip
    for name in ("tune.json", "hopper.leg"):
        assert (stopped / name).read_bytes() == (whole / name).read_bytes(), name
    # kept by a finished tune, to go further from: the same as the one never stopped
    assert (stopped / ".tune-journal.json").read_bytes() == (
        whole / ".tune-journal.json"
    ).read_bytes()
