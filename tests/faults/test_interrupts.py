"""Nothing recorded is lost (issue 18, item 2): a run stopped by Ctrl-C (SIGINT), SIGTERM, a
fall or a divergence still writes its run directory, and run.json says how it ended."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from legdsl.cli import main
from legdsl.sim.trajectory import Trajectory
from tests.faults.processes import wait_until_simulating

ROOT = Path(__file__).resolve().parents[2]
HOPPER = "creatures/hopper.leg"


def _start(generated: Path, out: Path) -> subprocess.Popen[str]:
    """A run of a billion simulated seconds: it must start at once and record as it goes (at
    10 Hz: the C backend simulates some 1000 s in the seconds before the signal, and the
    tests need not write and read back hundreds of thousands of samples)."""
    cmd = [sys.executable, "-m", "legdsl", "run", HOPPER, "--controller", "hop",
           "--set", "speed=1m/s", "--time", "1e9", "--record-rate", "10Hz",
           "--generated", str(generated), "--out", str(out)]  # fmt: skip
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    return subprocess.Popen(cmd, cwd=ROOT, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)  # fmt: skip


def _wait_and_send(proc: subprocess.Popen[str], signals: list[int], gap: float = 0.05) -> str:
    wait_until_simulating(proc)  # the hopper runs faster than real time: some simulated seconds
    for sig in signals:
        proc.send_signal(sig)
        time.sleep(gap)
    _, err = proc.communicate(timeout=60)
    return err


def _readable(out: Path) -> dict:
    info = json.loads((out / "run.json").read_text())
    trajectory = Trajectory.load(out)
    assert info["samples"] == len(trajectory) > 0
    assert np.all(np.diff(trajectory.t) > 0)
    return info


@pytest.mark.parametrize(
    ("signals", "gap", "code", "cause"),
    [
        ([signal.SIGINT], 0.0, 130, "SIGINT"),
        ([signal.SIGTERM], 0.0, 143, "SIGTERM"),
        ([signal.SIGINT, signal.SIGINT], 0.05, 130, "SIGINT"),  # the second one while writing
        # the others while the run loop is still winding down, before anything is written
        ([signal.SIGINT, signal.SIGINT, signal.SIGTERM, signal.SIGINT], 0.001, 130, "SIGINT"),
    ],
    ids=["ctrl-c", "sigterm", "ctrl-c-twice", "ctrl-c-held-down"],
)
def test_an_interrupted_long_run_keeps_what_it_recorded(
    generated: Path, tmp_path: Path, signals: list[int], gap: float, code: int, cause: str
) -> None:
    out = tmp_path / "run"
    proc = _start(generated, out)
    err = _wait_and_send(proc, signals, gap=gap)
    assert proc.returncode == code, err
    assert "Traceback" not in err and "internal error" not in err, err
    info = _readable(out)
    assert info["status"] == "interrupted"
    assert cause in info["cause"] and cause in info["message"]
    assert info["ended_at"] == info["sim_time"] > 0.5
    assert (out / "trajectory.csv").read_text().count("\n") == info["samples"] + 1
    if signals == [signal.SIGINT]:  # the other tools read it
        assert main(["metrics", str(out)]) == 0
        assert main(["animate", str(out), "--generated", str(generated),
                     "-o", str(tmp_path / "a.html")]) == 0  # fmt: skip
        assert (tmp_path / "a.html").stat().st_size > 0


def test_a_fall_and_a_divergence_are_written_with_their_cause(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    fell = tmp_path / "fell"
    argv = ["run", str(ROOT / HOPPER), "--generated", str(generated), "--time", "1",
            "--fall-height", "0.9m", "--out", str(fell)]  # fmt: skip
    assert main(argv) == 4  # the root starts at 0.95 m and sinks under 0.9 m as it lands
    info = _readable(fell)
    assert info["status"] == "fell" and "fell to" in info["cause"]
    diverged = tmp_path / "diverged"
    argv = ["run", str(ROOT / HOPPER), "--generated", str(generated), "--time", "1",
            "--dt", "10ms", "--out", str(diverged)]  # fmt: skip
    assert main(argv) == 3
    info = _readable(diverged)
    assert info["status"] == "diverged" and "Likely cause" in info["cause"]
    assert "internal error" not in capsys.readouterr().err


def test_the_recorder_grows_as_it_goes() -> None:
    """No allocation sized by the duration: the arrays start small and double."""
    from legdsl.sim.run_loop import INITIAL_ROWS
    from legdsl.sim.trajectory import empty

    t = empty(INITIAL_ROWS, 3, 3, 1, 1)
    t.q[:] = 1.0
    bigger = t.grown(2 * INITIAL_ROWS)
    assert len(bigger) == 2 * INITIAL_ROWS
    assert np.all(bigger.q[:INITIAL_ROWS] == 1.0) and np.all(bigger.q[INITIAL_ROWS:] == 0.0)
    assert np.all(bigger.state[INITIAL_ROWS:] == -1)
    assert np.all(np.isnan(bigger.speed_command[INITIAL_ROWS:]))


def test_a_killed_write_leaves_run_json_saying_incomplete(generated: Path, tmp_path: Path) -> None:
    """SIGKILL between run.json (incomplete) and the trajectory: the old run's run.json never
    stands beside a new trajectory, nor the new run.json beside the old trajectory (it did:
    an OOM kill while writing left them mixed)."""
    out = tmp_path / "run"
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"), LEGDSL_KILL_AT="2")
    cmd = [sys.executable, "-m", "legdsl", "run", HOPPER, "--time", "0.1",
           "--generated", str(generated), "--out", str(out)]  # fmt: skip
    older = ["run", str(ROOT / HOPPER), *cmd[5:]]
    assert main(older) == 0  # an older, complete run there first
    done = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True)
    assert done.returncode == -signal.SIGKILL, done.stderr
    assert json.loads((out / "run.json").read_text())["status"] == "incomplete"
    assert sorted(p.name for p in out.iterdir() if not p.name.startswith(".")) == ["run.json"]


# ------------------------------------------------------------------ the readers' outputs
def test_sigterm_unwinds_a_reader_as_ctrl_c_does() -> None:
    """animate, export-motion, replay and plot: SIGTERM raises, so that their temporary file
    is removed and ffmpeg stopped (Python's default ended the process on the spot)."""
    from legdsl.cli.process import sigterm_unwinds
    from legdsl.sim.run_loop import Interrupted

    before = signal.getsignal(signal.SIGTERM)
    with pytest.raises(Interrupted), sigterm_unwinds():
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(5)  # the handler raises before this ends
    assert signal.getsignal(signal.SIGTERM) == before


def test_a_second_sigterm_does_not_cut_the_unwinding_short() -> None:
    """SIGTERM held down: a second one raised again wherever the first's unwinding was, once
    as the context began to exit, which left its handlers installed and a traceback after
    "legdsl: terminated" (CI under load). Only the first is obeyed."""
    from legdsl.cli.process import sigterm_unwinds
    from legdsl.sim.run_loop import Interrupted

    before = signal.getsignal(signal.SIGTERM)
    unwound = []
    with pytest.raises(Interrupted), sigterm_unwinds():
        try:
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(5)  # the handler raises before this ends
        finally:
            os.kill(os.getpid(), signal.SIGTERM)  # lands at the next bytecode
            unwound.extend(range(3))
    assert unwound == [0, 1, 2]
    assert signal.getsignal(signal.SIGTERM) == before


def test_an_interrupted_video_leaves_no_file_and_no_ffmpeg(tmp_path: Path) -> None:
    """Ctrl-C between frames: ffmpeg is killed, not left to finish (with +faststart it wrote
    the file again by name after atomic_path had removed it: a hidden leftover)."""
    from external_tools import ffmpeg

    from legdsl.export.video import _write_mp4
    from legdsl.files import atomic_path

    ffmpeg()

    def frames() -> Iterator[np.ndarray]:
        for _ in range(5):
            yield np.zeros((16, 16, 3), dtype=np.uint8)
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt), atomic_path(tmp_path / "v.mp4") as tmp:
        _write_mp4(frames(), tmp, 30.0, 16, 16, lambda i: None)
    assert list(tmp_path.iterdir()) == []
    assert "ffmpeg" not in _children()  # else it finishes the file once legdsl exits


def _children() -> list[str]:
    """The names of this process's child processes (Linux's /proc)."""
    names = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
            if int(fields[1]) == os.getpid():
                names.append(stat.read_text().split("(", 1)[1].rsplit(")", 1)[0])
        except (OSError, IndexError, ValueError):
            continue
    return names


def test_an_interrupted_usd_export_leaves_no_layer(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    pytest.importorskip("pxr", reason="usd-core is in the test extra: pip install '.[test]'")
    from legdsl.export import usd

    def interrupted(motion: object, path: Path) -> None:
        path.write_text("#usda 1.0\n")  # half of a layer
        raise KeyboardInterrupt

    monkeypatch.setattr(usd, "build_stage", interrupted)
    with pytest.raises(KeyboardInterrupt):
        usd.write_usd(None, tmp_path / "m.usda", "usda")  # type: ignore[arg-type]
    assert list(tmp_path.iterdir()) == []


def test_a_directory_whose_write_was_cut_short_is_not_read(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Its trajectory.npz may be the older run's (a full disk refused the new one): metrics
    and animate measured and drew it without a word."""
    out = tmp_path / "run"
    assert main(["run", str(ROOT / HOPPER), "--time", "0.1", "--generated", str(generated),
                 "--out", str(out)]) == 0  # fmt: skip
    info = json.loads((out / "run.json").read_text())
    (out / "run.json").write_text(json.dumps(dict(info, status="incomplete")))
    for argv in (["metrics", str(out)], ["export-motion", str(out), "-o", str(tmp_path / "m.bvh")]):
        assert main(argv) == 2
        assert "was still being written when it stopped" in capsys.readouterr().err
    assert not (tmp_path / "m.bvh").exists()


def test_handlers_go_back_whole_though_one_raises_as_they_do(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A signal that came just before the handlers went back runs its handler at the next
    bytecode, anywhere in the restoring: its exception cut it short and left the rest
    installed, so a SIGTERM held down raised again after the command had ended ("legdsl:
    terminated", then a traceback at the exit; CI under load). They all go back, then the
    exception is raised."""
    import signal

    from legdsl import signals

    chosen = (signal.SIGUSR1, signal.SIGUSR2)
    before = [signal.getsignal(s) for s in chosen]
    real, calls = signal.signal, []

    def landing(sig: int, handler: object) -> object:
        calls.append(sig)
        if len(calls) == 3:  # the first handler put back: the pending signal's handler raises
            raise KeyboardInterrupt
        return real(sig, handler)

    monkeypatch.setattr(signal, "signal", landing)
    with pytest.raises(KeyboardInterrupt), signals.handled(chosen, lambda *_: None):
        pass
    monkeypatch.undo()
    assert [signal.getsignal(s) for s in chosen] == before
