"""Ctrl-C caught during a C build (a notebook's kernel goes on): the compiler processes it
started are ended and reaped, not left compiling into a removed directory, then zombies."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest
from runtime_helpers import child_pids, needs_c_compiler

from legdsl.codegen.c import build

ROOT = Path(__file__).resolve().parents[2]


@needs_c_compiler
def test_ctrl_c_during_a_build_leaves_no_compiler_behind(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    compiler = build.find_compiler()
    assert compiler is not None
    files = build.sources(ROOT / "generated" / "hopper", "hop")
    build.flags(compiler)  # its probe of the machine, before communicate is cut short
    before = child_pids()

    def interrupted(self: subprocess.Popen[str], *args: object, **kwargs: object) -> None:
        raise KeyboardInterrupt  # as the first wait for a compiler is cut short

    monkeypatch.setattr(subprocess.Popen, "communicate", interrupted)
    with pytest.raises(KeyboardInterrupt):
        build._compile("hopper", files, compiler, tmp_path, tmp_path / "hopper.so")
    monkeypatch.undo()
    assert child_pids() - before == set()  # none running, none a zombie
    assert list(tmp_path.iterdir()) == []  # and nothing half-built kept
