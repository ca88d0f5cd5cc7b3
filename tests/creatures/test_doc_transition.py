"""docs/quadruped.md's transition run: the controller segments printed under its `legdsl
metrics runs/q_transition` are what that command prints for the run the doc's command makes
(they once showed the root's displacement along x, bound +2.9% where metrics said +2.2%)."""

from __future__ import annotations

import contextlib
import io
import os
import re
from pathlib import Path

from conftest import ROOT
from runtime_helpers import legdsl_in_process, needs_c_compiler

from legdsl.cli import main

pytestmark = needs_c_compiler

DOC = ROOT / "docs" / "quadruped.md"


def _doc_command_and_segments() -> tuple[list[str], list[str]]:
    text = DOC.read_text()
    at = text.index("## Changing gait: the issue's transition run")
    block = re.search(r"\n    (legdsl run .*?--out runs/q_transition)\n", text[at:], re.S)
    assert block is not None
    command = block.group(1).replace("\\\n", " ").split()
    head = "    controller segments ("
    start = text.index(head, at)
    lines = []
    for line in text[start:].splitlines():
        if not line.startswith("    "):
            break
        lines.append(line[4:])
    return command, lines


def test_the_transition_segments_are_what_metrics_prints(generated: Path, tmp_path: Path) -> None:
    command, documented = _doc_command_and_segments()
    assert command[:3] == ["legdsl", "run", "creatures/quadruped.leg"] and len(documented) == 5
    out = tmp_path / "q_transition"
    argv = [*command[1:-2], "--out", str(out), "--backend", "c", "--generated", str(generated)]
    argv[1] = str(ROOT / argv[1])
    here = os.getcwd()
    os.chdir(tmp_path)
    try:
        code, err = legdsl_in_process(argv)
        assert code == 0, err
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed), contextlib.redirect_stderr(io.StringIO()):
            assert main(["metrics", str(out)]) == 0
    finally:
        os.chdir(here)
    lines = printed.getvalue().splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("controller segments ("))
    assert lines[start : start + 5] == documented
