"""A compiler that hangs (``LEGDSL_CC`` a wrapper gone wrong): off a terminal a run said nothing
until it was killed, and then "finishing runs/X/ first" though nothing was being written.
Now a compiler still running is said to be, by name, with its units and its seconds."""

from __future__ import annotations

import io
import re
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import CREATURES
from runtime_helpers import needs_c_compiler

from legdsl.cli import main
from legdsl.cli.run import _Interrupts
from legdsl.codegen.c import build
from legdsl.sim import c_library
from legdsl.sim.run_loop import Interrupted

GENERATED = Path(__file__).resolve().parents[2] / "generated"


def slow_compiler(tmp_path: Path) -> Path:
    """A compiler that takes 2 s over dynamics.c (not its link), then compiles it."""
    script = tmp_path / "slow-cc"
    script.write_text('#!/bin/sh\ncase "$*" in */dynamics.c) sleep 2;; esac\nexec gcc "$@"\n')
    script.chmod(0o755)
    return script


@needs_c_compiler
def test_a_compiler_still_running_is_said_by_name_with_its_seconds(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("LEGDSL_CACHE", str(tmp_path / "cache"))
    monkeypatch.setenv("LEGDSL_CC", str(slow_compiler(tmp_path)))
    monkeypatch.setattr(build, "PATIENCE", (0.5, 1.0))
    told: list[str] = []
    built = build.build("hopper", build.sources(GENERATED / "hopper", "hop"), starting=told.append)
    assert not built.cached and told[0].startswith("building the C library of hopper")
    notes = [note for note in told[1:] if " on the link " not in note]  # a busy machine's
    assert notes, told
    shape = re.escape(f"{build.STILL} the C library of hopper: {tmp_path / 'slow-cc'} (LEGDSL_CC)")
    shape += r" has run (\d+) s on ([a-z_.]+(, [a-z_.]+)*) "
    shape += re.escape("(if it hangs, stop it and set LEGDSL_CC to another compiler)")
    matched = [re.fullmatch(shape, note) for note in notes]
    assert all(matched), notes
    seconds = [int(m[1]) for m in matched if m]
    assert "dynamics.c" in matched[0][2].split(", ")  # type: ignore[index]  # the slow one
    assert seconds == sorted(seconds), notes


@needs_c_compiler
def test_off_a_terminal_a_run_says_its_compiler_is_still_running(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("LEGDSL_CACHE", str(tmp_path / "cache"))
    monkeypatch.setenv("LEGDSL_CC", str(slow_compiler(tmp_path)))
    monkeypatch.setattr(build, "PATIENCE", (0.5, 1.0))
    monkeypatch.setattr(c_library, "_BY_STAT", {})
    monkeypatch.setattr(c_library, "_TRUSTED", {})
    said = io.StringIO()  # a log: not a terminal
    monkeypatch.setattr(sys, "stderr", said)
    argv = ["run", str(CREATURES / "hopper.leg"), "--controller", "hop", "--time", "0.01"]
    argv += ["--backend", "c", "--out", str(tmp_path / "run")]
    assert main(argv) == 0
    text = said.getvalue()
    assert f"legdsl: {build.STILL} the C library of hopper-hop: " in text, text
    assert "legdsl: building the C library" not in text  # the start is a terminal's alone


def test_a_second_signal_before_the_simulation_says_no_directory_is_finished(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``timeout`` sends SIGTERM to the run and then to its process group: the second, while the
    first unwound a hung build, said "finishing runs/cch/ first", which was never written."""
    interrupts = _Interrupts(tmp_path / "runs")
    with pytest.raises(Interrupted):
        interrupts(signal.SIGTERM, None)
    interrupts(signal.SIGTERM, None)
    assert capsys.readouterr().err == "" and interrupts.late == ["SIGTERM"]
    interrupts.started = True  # a stopped simulation's run is written: that one is finished
    interrupts(signal.SIGTERM, None)
    assert f"finishing {tmp_path / 'runs'}/ first" in capsys.readouterr().err


class _EndedAsItWasWaitedFor:
    """A compiler whose wait timed out and which ended before it was asked whether it runs."""

    def __init__(self) -> None:
        self.waits = 0

    def communicate(self, timeout: float | None = None) -> tuple[str, str]:
        self.waits += 1
        if self.waits == 1:
            raise subprocess.TimeoutExpired("cc", timeout or 0.0)
        return "", ""

    def poll(self) -> int:
        return 0


def test_no_note_names_no_unit_when_the_compiler_ended_meanwhile(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """CI under load: 'has run 3 s on  (if it hangs ...' named no unit, the one waited for
    having ended between its wait's timeout and the question which still run."""
    monkeypatch.setattr(build, "PATIENCE", (0.0, 1.0))
    told: list[str] = []
    process = _EndedAsItWasWaitedFor()
    said = build._outputs([process], ["dynamics.c"], "hopper", told.append)  # type: ignore[list-item]
    assert said == [""] and told == [] and process.waits == 2
