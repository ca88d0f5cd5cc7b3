"""Ctrl-C caught during a C build (a notebook's kernel goes on): the compiler processes it
started are ended and reaped, not left compiling into a removed directory, then zombies."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import time
from pathlib import Path
from typing import Any

import pytest
from runtime_helpers import child_pids, needs_c_compiler

from legdsl.codegen.c import build

ROOT = Path(__file__).resolve().parents[2]


def compiling_in(folder: Path) -> list[str]:
    """The command lines of the processes (of any parent) that name a file in ``folder``."""
    found = []
    for proc in Path("/proc").iterdir():
        try:
            words = (proc / "cmdline").read_bytes().split(b"\0")
        except OSError:
            continue
        if any(str(folder).encode() in word for word in words):
            found.append(b" ".join(words).decode(errors="replace"))
    return found


@needs_c_compiler
def test_ctrl_c_during_a_build_leaves_no_compiler_behind(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    compiler = build.find_compiler()
    assert compiler is not None
    files = build.sources(ROOT / "generated" / "quadruped", "trot")  # seconds of cc1
    build.flags(compiler)  # its probe of the machine, before communicate is cut short
    before = child_pids()

    def interrupted(self: subprocess.Popen[str], *args: object, **kwargs: object) -> None:
        time.sleep(0.3)  # gcc has started its passes (cc1) by then
        raise KeyboardInterrupt  # as the first wait for a compiler is cut short

    monkeypatch.setattr(subprocess.Popen, "communicate", interrupted)
    with pytest.raises(KeyboardInterrupt):
        build._compile("quadruped", files, compiler, tmp_path, tmp_path / "quadruped.so")
    monkeypatch.undo()
    assert child_pids() - before == set()  # none running, none a zombie
    for _ in range(6):  # killed, not yet gone: a moment (unkilled, cc1 goes on for a second)
        if not compiling_in(tmp_path):
            break
        time.sleep(0.05)
    assert compiling_in(tmp_path) == []  # nor gcc's passes (cc1), which wrote on into it
    assert list(tmp_path.iterdir()) == []  # and nothing half-built kept


@needs_c_compiler
@pytest.mark.parametrize("when", ["a unit", "the probe"])
def test_ctrl_c_as_a_compiler_starts_leaves_none_behind(
    when: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A Ctrl-C landing inside ``Popen``, once the compiler is started but before it is known
    (random API interrupts, seed 21090): the compiler ran on, then stayed a zombie after the
    call. A process is now started and noted with the signals held, the Ctrl-C coming after."""
    compiler = build.find_compiler()
    assert compiler is not None
    files = build.sources(ROOT / "generated" / "hopper", "hop")
    build.flags(compiler)  # its probe of the machine, before the interrupted start
    before = child_pids()
    start = subprocess.Popen.__init__

    def interrupted(self: subprocess.Popen[str], *args: Any, **kwargs: Any) -> None:
        start(self, *args, **kwargs)
        os.kill(os.getpid(), signal.SIGINT)  # Ctrl-C, as Popen returns

    monkeypatch.setattr(subprocess.Popen, "__init__", interrupted)
    with pytest.raises(KeyboardInterrupt):
        if when == "a unit":
            build._compile("hopper", files, compiler, tmp_path, tmp_path / "hopper.so")
        else:
            build.probe(compiler, tmp_path)
    monkeypatch.undo()
    assert child_pids() - before == set()  # none running, none a zombie


def test_a_ctrl_c_as_a_compiler_process_is_dropped_is_raised_not_lost(
    monkeypatch: pytest.MonkeyPatch, capfd: pytest.CaptureFixture[str]
) -> None:
    """Random API interrupts, seed 21182 (Ctrl-C held down through a build): one landed in a
    finished compiler's ``Popen.__del__``, as the build dropped it: "Exception ignored", a
    traceback, and the Ctrl-C lost. The processes are dropped with the signals held."""
    true = shutil.which("true")
    assert true is not None
    finalize = subprocess.Popen.__del__

    def interrupted(self: subprocess.Popen[str]) -> None:
        if self.args == [true]:
            os.kill(os.getpid(), signal.SIGINT)  # Ctrl-C, in the finalizer
        finalize(self)

    monkeypatch.setattr(subprocess.Popen, "__del__", interrupted)
    with pytest.raises(KeyboardInterrupt):
        build._probe_run([true], 5)
    assert "Exception ignored" not in capfd.readouterr().err
