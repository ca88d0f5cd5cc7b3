"""Signals at moments no one picked (docs/runtime.md, Interrupts).

Each draw, from its seed, picks a command (a compile, a run, an export or video of a finished
run, a sweep, a tune), a signal (SIGINT, SIGTERM, SIGHUP, SIGQUIT, two SIGINTs in a row, or SIGINT held down),
to the command alone or to its process group (as a terminal's Ctrl-C), and a delay anywhere in
the command's life, from its imports to its last writes (the command's undisturbed duration
is measured once, by the reference run each draw is compared with). The command must exit
with 0 (it finished first) or 128 + the signal (or die of the signal before legdsl had set
its handlers, which a shell reports the same), say no traceback, leave no process behind,
leave its outputs complete or saying that they are not, and the same command run again must
finish with the outputs of an undisturbed one: the C library cache and the generated modules
were not left corrupt.

    LEGDSL_RANDOM_SIGNALS=80 LEGDSL_RANDOM_SIGNAL_SEED=0 pytest tests/faults/test_random_signals.py
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from runtime_helpers import child_pids

ROOT = Path(__file__).resolve().parents[2]
COUNT = int(os.environ.get("LEGDSL_RANDOM_SIGNALS", "1"))
FIRST = int(os.environ.get("LEGDSL_RANDOM_SIGNAL_SEED", "0"))
SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP, signal.SIGQUIT)
# hidden files a command keeps on purpose: the locks (held by flock, not by their presence)
# and a stopped tune's journal, from which the same command goes on
KEPT = {".sweep.lock", ".tune.lock", ".tune-journal.json"}
HAS_FFMPEG = shutil.which("ffmpeg") is not None

HOP = ["creatures/hopper.leg", "--controller", "hop"]
SWEEP = ["sweep", *HOP, "--grid", "speed=0.5:1.5:3", "--time", "1", "--from", "0.5",
         "--jobs", "2", "--generated", "gen", "--out", "out"]  # fmt: skip
TUNE = ["tune", *HOP, "--param", "k_speed=0.02:0.2", "--speeds", "1", "--time", "1.5",
        "--from", "0.5", "--generations", "2", "--popsize", "3", "--seed", "1", "--jobs", "2",
        "--generated", "gen", "--out", "out"]  # fmt: skip


def _commands() -> list[tuple[str, list[str]]]:
    """(kind, argv) of every command a draw may pick; paths are relative to a scratch dir."""
    commands = [
        ("compile", ["compile", f"creatures/{name}.leg", "--out", "out"])
        for name in ("hopper", "kangaroo", "biped", "quadruped")
    ]
    for name in ("hopper", "kangaroo"):
        for backend in ("c", "python"):
            for animate in ([], ["--animate"]):
                argv = ["run", f"creatures/{name}.leg", "--time", "0.5", "--backend", backend,
                        "--generated", "gen", "--out", "out", *animate]  # fmt: skip
                commands.append(("run", argv))
    commands.append(
        ("export", ["export-motion", "finished", "-o", "out/motion.glb", "--generated", "gen"])
    )
    if HAS_FFMPEG:
        commands.append(("video", ["animate", "finished", "--video", "out/v.mp4",
                                   "--size", "320x180", "--generated", "gen"]))  # fmt: skip
    commands.append(("video", ["animate", "finished", "--video", "out/v.gif",
                               "--size", "160x90", "--generated", "gen"]))  # fmt: skip
    commands += [("sweep", SWEEP), ("tune", TUNE)]
    return commands


@dataclass
class Draw:
    seed: int
    kind: str
    argv: list[str]
    signals: list[int]
    gap: float  # between two SIGINTs
    whole_group: bool
    fraction: float  # of the command's undisturbed duration
    held: bool = False  # Ctrl-C held down: sent again every 0.2 ms until the command ends

    def __str__(self) -> str:
        names = "+".join(signal.Signals(s).name for s in self.signals)
        names += " held down" if self.held else ""
        to = "its process group" if self.whole_group else "the command"
        return (f"seed {self.seed}: legdsl {' '.join(self.argv)}; {names} to {to} at "
                f"{self.fraction:.3f} of its duration")  # fmt: skip


def draw(seed: int) -> Draw:
    rng = np.random.default_rng(seed)
    commands = _commands()
    kind, argv = commands[int(rng.integers(len(commands)))]
    if rng.random() < 0.2:
        signals, gap = [signal.SIGINT, signal.SIGINT], float(rng.uniform(0.0, 0.3))
    else:
        signals, gap = [SIGNALS[int(rng.integers(len(SIGNALS)))]], 0.0
    whole_group = signals[0] == signal.SIGINT and bool(rng.random() < 0.5)
    # a third of the draws in the first tenth (imports, compiling, building), the rest anywhere
    # up to just past the end
    fraction = float(rng.uniform(0.0, 0.1) if rng.random() < 1 / 3 else rng.uniform(0.0, 1.05))
    # drawn apart, so that the draws above stay those of their seeds
    held = signals[0] == signal.SIGINT and bool(np.random.default_rng([seed, 1]).random() < 0.5)
    return Draw(seed, kind, argv, signals, gap, whole_group, fraction, held)


# ------------------------------------------------------------------------ running commands
def _scratch(base: Path) -> Path:
    """A fresh directory to run in: ``creatures`` linked, an empty ``gen`` for the generated
    modules and an empty C library cache (``LEGDSL_CACHE``), so that a command compiles and
    builds them itself, a signal able to come as it writes them."""
    base.mkdir(parents=True)
    (base / "creatures").symlink_to(ROOT / "creatures")
    (base / "gen").mkdir()
    return base


def _env(scratch: Path) -> dict[str, str]:
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"), LEGDSL_CACHE=str(scratch / "cache"))
    env.pop("LEGDSL_KILL_AT", None)
    return env


def _start(argv: list[str], scratch: Path) -> subprocess.Popen[str]:
    return subprocess.Popen(
        ["nice", "-n", "10", sys.executable, "-m", "legdsl", *argv], cwd=scratch,
        env=_env(scratch), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        start_new_session=True,
    )  # fmt: skip


def _finish(proc: subprocess.Popen[str], what: str) -> tuple[str, str]:
    try:
        out, err = proc.communicate(timeout=180)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
        pytest.fail(f"{what}: still running after 180 s\n{err}")
    # nobody left in its session: a worker, a compiler, ffmpeg
    deadline = time.monotonic() + 10
    while True:
        try:
            os.killpg(proc.pid, 0)
        except ProcessLookupError:
            break
        if time.monotonic() > deadline:
            os.killpg(proc.pid, signal.SIGKILL)
            pytest.fail(f"{what}: processes left running after it ended\n{err}")
        time.sleep(0.05)
    return out, err


def _hold_down(proc: subprocess.Popen[str], sig: int, whole_group: bool = False) -> None:
    """``sig`` every 0.2 ms until the command has ended (a key held down), to it or its whole
    process group (as a terminal sends Ctrl-C)."""
    while proc.poll() is None:
        with contextlib.suppress(ProcessLookupError, PermissionError):
            (os.killpg if whole_group else os.kill)(proc.pid, sig)
        time.sleep(0.0002)


def _run(argv: list[str], scratch: Path, what: str) -> float:
    started = time.monotonic()
    proc = _start(argv, scratch)
    _, err = _finish(proc, what)
    assert proc.returncode == 0, f"{what}: exit {proc.returncode}\n{err}"
    assert "Traceback" not in err and "internal error" not in err, f"{what}\n{err}"
    return time.monotonic() - started


_references: dict[tuple[str, ...], tuple[Path, float]] = {}


def _finished_run(base: Path) -> Path:
    """A finished run for the export and the video to read (once a session)."""
    key = ("finished",)
    if key not in _references:
        scratch = _scratch(base / "finished-run")
        argv = ["run", "creatures/hopper.leg", "--time", "0.5", "--generated", "gen",
                "--out", "out"]  # fmt: skip
        _references[key] = (scratch, _run(argv, scratch, "the finished run"))
    return _references[key][0]


def _prepare(argv: list[str], scratch: Path, base: Path) -> None:
    if "finished" in argv:
        (scratch / "finished").symlink_to(_finished_run(base) / "out")
        shutil.copytree(_finished_run(base) / "gen", scratch / "gen", dirs_exist_ok=True)
        (scratch / "out").mkdir()


def _reference(argv: list[str], base: Path) -> tuple[Path, float]:
    """The command's undisturbed outputs and duration (once a session per command)."""
    key = tuple(argv)
    if key not in _references:
        scratch = _scratch(base / f"reference-{len(_references)}")
        _prepare(argv, scratch, base)
        _references[key] = (scratch, _run(argv, scratch, f"legdsl {' '.join(argv)}"))
    return _references[key]


# ------------------------------------------------------------------------ what each leaves
def _hidden_leftovers(scratch: Path, workers: bool = False) -> list[str]:
    """Hidden files left in the outputs and caches. A sweep's or tune's worker is ended at once
    by its command's SIGTERM (``api.workers``): a C build it had begun leaves its sources in
    the cache, which a later build removes after an hour (``cache.LEFTOVER_SECONDS``; seeds
    45 and 71)."""
    found = []
    for path in (scratch / "out", scratch / "gen", scratch / "cache"):
        if path.is_dir():
            found += [str(p.relative_to(scratch)) for p in path.rglob(".*") if p.name not in KEPT]
    if workers:
        found = [f for f in found if not re.fullmatch(r"cache/\.[\w.-]+-src-\w+", f)]
    return found


def _tree(directory: Path) -> dict[str, bytes]:
    return {
        str(p.relative_to(directory)): p.read_bytes()
        for p in sorted(directory.rglob("*"))
        if p.is_file() and p.name not in KEPT
    }


def _rows(table: Path) -> set[str]:
    return set(table.read_text().splitlines()[1:]) if table.is_file() else set()


def _check_stopped(d: Draw, scratch: Path, reference: Path, stopped: bool) -> None:
    """The outputs of the signalled command: complete, or saying that they are not."""
    out = scratch / "out"
    if d.kind == "compile":
        name = Path(d.argv[1]).stem
        if stopped and not (out / name).is_dir():
            return
        assert _tree(out) == _tree(reference / "out"), "a module set half written"
    elif d.kind == "run":
        if not (out / "run.json").is_file():
            assert stopped, "a finished run without run.json"
            return
        from legdsl.sim.trajectory import Trajectory

        info = json.loads((out / "run.json").read_text())
        if info["status"] == "incomplete":
            assert stopped
            return
        if stopped and info["status"] == "ok":  # the signal came once the run was written
            whole = Trajectory.load(reference / "out")  # (seed 30017: SIGTERM at 0.96)
            assert np.array_equal(Trajectory.load(out).q, whole.q), "an 'ok' run cut short"
            return
        assert info["status"] == ("interrupted" if stopped else "ok"), info
        assert info["samples"] == len(Trajectory.load(out))
        if stopped:
            assert info["cause"] in {signal.Signals(s).name for s in d.signals}, info
        elif "--animate" in d.argv:
            assert (out / "animation.html").stat().st_size > 0
    elif d.kind in ("export", "video"):
        target = Path(d.argv[d.argv.index("-o" if d.kind == "export" else "--video") + 1])
        if stopped and not (scratch / target).exists():
            return
        assert (scratch / target).stat().st_size == (reference / target).stat().st_size
    elif d.kind == "sweep":
        from legdsl.api.sweep import read_table

        read_table(out / "sweep.csv")  # readable: no row half written but the last, dropped
        rows = _rows(out / "sweep.csv")
        assert rows <= _rows(reference / "out" / "sweep.csv"), "rows of no undisturbed run"
        if not stopped:
            assert rows == _rows(reference / "out" / "sweep.csv")
    elif d.kind == "tune":
        if not (out / "tune.json").is_file():
            assert stopped and not (out / "hopper.leg").exists()
            return
        ended = json.loads((out / "tune.json").read_text())["ended"]
        assert ended in (("interrupted", "terminated", "finished") if stopped else ("finished",))
        assert (out / "hopper.leg").is_file() and (out / "tune.png").stat().st_size > 0


def _check_again(d: Draw, scratch: Path, reference: Path) -> None:
    """The same command, run again undisturbed: the undisturbed outputs."""
    out, ref = scratch / "out", reference / "out"
    if d.kind == "compile":
        assert _tree(out) == _tree(ref)
    elif d.kind == "run":
        from legdsl.sim.trajectory import Trajectory

        assert json.loads((out / "run.json").read_text())["status"] == "ok"
        again, undisturbed = Trajectory.load(out), Trajectory.load(ref)
        assert len(again) == len(undisturbed)
        for field in ("t", "q", "v", "force", "state"):
            assert np.array_equal(getattr(again, field), getattr(undisturbed, field)), field
    elif d.kind == "export":
        assert (out / "motion.glb").read_bytes() == (ref / "motion.glb").read_bytes()
    elif d.kind == "video":
        target = Path(d.argv[d.argv.index("--video") + 1])
        assert (scratch / target).stat().st_size == (reference / target).stat().st_size
    elif d.kind == "sweep":
        assert _rows(out / "sweep.csv") == _rows(ref / "sweep.csv")
    elif d.kind == "tune":
        for name in ("tune.json", "hopper.leg"):
            assert (out / name).read_bytes() == (ref / name).read_bytes(), name
        journal = (out / ".tune-journal.json", ref / ".tune-journal.json")  # a finished tune's
        assert journal[0].read_bytes() == journal[1].read_bytes()


def _in_pythons_own_start(code: int, sig: int, err: str) -> bool:
    """A Ctrl-C in the interpreter's own start-up, before the first line of legdsl: as ``site``
    runs the ``.pth`` files of the installed packages (seed 30041, at 2 ms), Python itself stops
    with "Fatal Python error: init_import_site" and exit 1; as ``-m`` imports ``runpy`` (seed
    31048), with "Could not import runpy module" and a traceback of its own importer alone.
    No program can change either."""
    site = code == 1 and err.startswith("Fatal Python error: init_import_site")
    runpy = err.startswith("Could not import runpy module") and "legdsl" not in err
    return sig == signal.SIGINT and (site or runpy) and err.rstrip().endswith("KeyboardInterrupt")


# ------------------------------------------------------------------------ the draws
@pytest.mark.parametrize("seed", range(FIRST, FIRST + COUNT))
def test_a_signal_at_a_random_moment(seed: int, tmp_path_factory: pytest.TempPathFactory) -> None:
    d = draw(seed)
    base = tmp_path_factory.getbasetemp() / "random-signals"
    reference, duration = _reference(d.argv, base)
    scratch = _scratch(base / f"seed-{seed}")
    _prepare(d.argv, scratch, base)
    try:
        proc = _start(d.argv, scratch)
        time.sleep(d.fraction * duration)
        for i, sig in enumerate(d.signals):
            if i:
                time.sleep(d.gap)
            try:
                (os.killpg if d.whole_group else os.kill)(proc.pid, sig)
            except ProcessLookupError:  # it had finished
                break
        if d.held:
            _hold_down(proc, signal.SIGINT, d.whole_group)
        _, err = _finish(proc, str(d))
        code = proc.returncode
        sig = d.signals[0]
        if not _in_pythons_own_start(code, sig, err):
            assert code in (0, 128 + sig, -sig), f"{d}: exit {code}\n{err}"
            assert "Traceback" not in err and "internal error" not in err, f"{d}\n{err}"
            assert "Exception ignored" not in err, f"{d}\n{err}"
        leftovers = _hidden_leftovers(scratch, workers="--jobs" in d.argv)
        assert not leftovers, f"{d}: left {leftovers}\n{err}"
        _check_stopped(d, scratch, reference, stopped=code != 0)
        _run(d.argv, scratch, f"{d}, run again")
        _check_again(d, scratch, reference)
    except AssertionError as e:
        raise AssertionError(f"{d}: {e}") from e
    shutil.rmtree(scratch)


NOTING_PARENT = """
import signal, time
from legdsl.pipeline.forked import Forked
signal.signal(signal.SIGTERM, lambda signum, frame: None)  # noted, as a run writing its files
def work(item):
    time.sleep(0.5)
    return b"x" * (4 << 20)  # more than a pipe holds: blocks until read
forked = Forked(work, [0], 1)
forked.close()  # as after an interrupt: nothing read
"""


def test_a_stopped_compile_does_not_wait_for_its_controller_processes() -> None:
    """A part of seeds 5 and 14: a compile lowers controllers in forked processes. They
    inherited a handler that notes SIGTERM and goes on (a run's), so close()'s terminate() did
    not end them; each then blocked writing its result to a pipe no one read, and the command
    waited for it for ever."""
    done = subprocess.run([sys.executable, "-c", NOTING_PARENT], env=_env(Path("/nonexistent")),
                          capture_output=True, text=True, timeout=60)  # fmt: skip
    assert done.returncode == 0, done.stderr


@pytest.mark.parametrize(
    ("argv", "said", "sig"),
    [
        (["compile", "creatures/biped.leg", "--out", "out"], "lowering 14 DOF", signal.SIGQUIT),
        (["run", "creatures/kangaroo.leg", "--controller", "hop", "--time", "0.1", "--backend",
          "python", "--generated", "gen", "--out", "run"], "compiling", signal.SIGTERM),
    ],
)  # fmt: skip
def test_a_signal_while_compiling_ends_the_command_and_its_controller_processes(
    argv: list[str], said: str, sig: int, tmp_path: Path
) -> None:
    """Seeds 5 and 14: SIGQUIT (or SIGTERM) while a command compiled killed it on the spot (no
    handler there), and its forked controller processes, orphaned, blocked for ever writing to
    pipes they held open themselves: the terminal got its prompt back, the processes stayed
    (and a caller reading the command's output waited for ever). It now unwinds: the processes
    are stopped, one line says so, exit status 128 + the signal; and a process whose command is
    gone (SIGKILL) ends at its next write."""
    scratch = _scratch(tmp_path / "s")
    proc = _start(argv, scratch)
    assert proc.stderr is not None
    seen = ""
    while said not in seen:  # the compile has begun
        line = proc.stderr.readline()
        assert line, f"ended before '{said}': {seen}"
        seen += line
    proc.send_signal(sig)
    _, err = _finish(proc, " ".join(argv))  # and nobody left in its session
    assert proc.returncode in (128 + sig, -sig), seen + err
    if proc.returncode > 0:  # the handlers were in place: one line
        assert f"legdsl: terminated ({signal.Signals(sig).name})" in err, seen + err
    assert "Traceback" not in err, err


def test_ctrl_c_pressed_again_and_again_as_an_interrupted_command_ends(tmp_path: Path) -> None:
    """Seed 43: a second Ctrl-C 0.1 s after the first, as the interrupted command flushed its
    output or ran Python's exit handlers, printed a traceback under "legdsl: interrupted"."""
    scratch = _scratch(tmp_path / "s")
    argv = ["run", "creatures/kangaroo.leg", "--time", "0.5", "--generated", "gen", "--out", "o"]
    proc = _start(argv, scratch)
    assert proc.stderr is not None
    while "compiling" not in (line := proc.stderr.readline()):
        assert line, "ended before compiling"
    _hold_down(proc, signal.SIGINT)
    _, err = _finish(proc, " ".join(argv))
    assert proc.returncode in (130, -signal.SIGINT), err
    assert "Traceback" not in err and "Exception ignored" not in err, err


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads Linux's /proc")
def test_ctrl_c_held_down_at_a_terminal_as_a_sweep_starts_its_workers(tmp_path: Path) -> None:
    """A terminal's Ctrl-C goes to the command's whole process group: a worker forked a moment
    before, not yet ignoring it, printed "Exception ignored in: <bound method Random.seed ...>"
    and a KeyboardInterrupt (random's fork handler; 3 of 5 tries). Workers start with Ctrl-C
    held back, and take it once they ignore it."""
    scratch = _scratch(tmp_path / "s")
    shutil.copytree(ROOT / "generated" / "hopper", scratch / "gen" / "hopper")
    _run(["run", *HOP, "--time", "0.1", "--generated", "gen"], scratch, "the C library built")
    proc = _start(SWEEP, scratch)
    while proc.poll() is None and not child_pids(proc.pid):
        time.sleep(0.0005)
    _hold_down(proc, signal.SIGINT, whole_group=True)  # at the terminal
    _, err = _finish(proc, " ".join(SWEEP))
    assert proc.returncode in (130, -signal.SIGINT), err
    assert "Traceback" not in err and "Exception ignored" not in err, err


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads Linux's /proc")
@pytest.mark.parametrize("held", [False, True])
def test_ctrl_c_at_a_terminal_as_a_dask_cluster_starts(held: bool, tmp_path: Path) -> None:
    """``--dask local``: a Ctrl-C as the cluster's processes started printed each one's
    KeyboardInterrupt from its imports, and the cluster it left half made failed distributed's
    exit hook (AssertionError: Status.init); later, a worker that took it printed its own. A
    Ctrl-C as they start is lost (they start ignoring it, and keep it); one after stops."""
    pytest.importorskip("distributed")
    scratch = _scratch(tmp_path / "s")
    shutil.copytree(ROOT / "generated" / "hopper", scratch / "gen" / "hopper")
    _run(["run", *HOP, "--time", "0.1", "--generated", "gen"], scratch, "the C library built")
    argv = [*SWEEP[:-2], "--dask", "local", "--out", "out"]
    proc = _start(argv, scratch)
    while proc.poll() is None and not child_pids(proc.pid):  # the cluster's processes start
        time.sleep(0.0005)
    if held:
        _hold_down(proc, signal.SIGINT, whole_group=True)
    else:  # at once, and again a second later should the first come as they start
        for _ in range(2):
            with contextlib.suppress(ProcessLookupError):
                os.killpg(proc.pid, signal.SIGINT)
            time.sleep(1.0)
    _, err = _finish(proc, " ".join(argv))
    assert proc.returncode in (0, 130, -signal.SIGINT), err  # 0: it ended before the second
    assert "Traceback" not in err and "Exception ignored" not in err, err


def test_sigterm_as_a_compile_starts_its_controller_processes_ends_it(tmp_path: Path) -> None:
    """SIGTERM landing in the fork handlers of a controller process starting (logging's lock)
    was printed as "Exception ignored ... Interrupted: SIGTERM" and dropped: the compile went on
    and ended 0. The ending signals are held back while a process starts, as Ctrl-C is."""
    scratch = _scratch(tmp_path / "s")
    argv = ["compile", "creatures/biped.leg", "--out", "out"]
    proc = _start(argv, scratch)
    assert proc.stderr is not None
    while "checked in" not in (line := proc.stderr.readline()):  # the processes start next
        assert line, "ended before checking"
    _hold_down(proc, signal.SIGTERM)
    _, err = _finish(proc, " ".join(argv))
    assert proc.returncode in (143, -signal.SIGTERM), err
    assert "Traceback" not in err and "Exception ignored" not in err, err
