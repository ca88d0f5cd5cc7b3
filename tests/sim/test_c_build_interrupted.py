"""Ctrl-C caught during a C build (a notebook's kernel goes on): the compiler processes it
started are ended and reaped, not left compiling into a removed directory, then zombies."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest
from runtime_helpers import needs_c_compiler

from legdsl.codegen.c import build

ROOT = Path(__file__).resolve().parents[2]


def children() -> set[int]:
    found = set()
    for pid in os.listdir("/proc"):
        if pid.isdigit():
            try:
                fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if fields[1] == str(os.getpid()):
                found.add(int(pid))
    return found


@needs_c_compiler
def test_ctrl_c_during_a_build_leaves_no_compiler_behind(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    compiler = build.find_compiler()
    assert compiler is not None
    files = build.sources(ROOT / "generated" / "hopper", "hop")
    build.flags(compiler)  # its probe of the machine, before communicate is cut short
    before = children()

    def interrupted(self: subprocess.Popen[str], *args: object, **kwargs: object) -> None:
        raise KeyboardInterrupt  # as the first wait for a compiler is cut short

    monkeypatch.setattr(subprocess.Popen, "communicate", interrupted)
    with pytest.raises(KeyboardInterrupt):
        build._compile("hopper", files, compiler, tmp_path, tmp_path / "hopper.so")
    monkeypatch.undo()
    assert children() - before == set()  # none running, none a zombie
    assert list(tmp_path.iterdir()) == []  # and nothing half-built kept
