"""The figures the creature docs draw with a command they give are what that command draws
today: docs/img/kangaroo-figure6.png from docs/kangaroo.md's `legdsl run ... --out runs/k5`
and `legdsl plot runs/k5 --from 10 --to 11.1` (it once showed a run from before a change of
the kangaroo's speed trim, 6.6% of its pixels apart). Fonts may differ from machine to machine,
so a few pixels may differ; the curves of another run do not."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import numpy as np
import pytest
from pixels import pixels
from runtime_helpers import needs_c_compiler

from legdsl.cli import main

pytestmark = needs_c_compiler

ROOT = Path(__file__).resolve().parents[2]
# (doc, picture, the run directory of the commands that draw it, the picture's name there)
PICTURES = [("docs/kangaroo.md", "docs/img/kangaroo-figure6.png", "runs/k5", "figure6.png")]


@pytest.mark.parametrize("doc, picture, run, drawn", PICTURES, ids=lambda v: Path(v).name)
def test_a_doc_picture_is_what_its_commands_draw(
    generated: Path, tmp_path: Path, doc: str, picture: str, run: str, drawn: str
) -> None:
    text = (ROOT / doc).read_text(encoding="utf-8")
    commands = [
        shlex.split(line.strip())[1:]
        for line in text.splitlines()
        if re.match(
            rf"\s+legdsl (run .* --out {re.escape(run)}|plot {re.escape(run)}( .*)?)$", line
        )
    ]
    assert [c[0] for c in commands] == ["run", "plot"], f"{doc}: the commands for {run} moved"
    out = tmp_path / run
    for command in commands:
        args = [
            str(out) if a == run else str(ROOT / a) if a.endswith(".leg") else a for a in command
        ]
        extra = ["--generated", str(generated)] if args[0] == "run" else []
        assert main([*args, *extra]) == 0, f"legdsl {shlex.join(command)}"
    ours, theirs = pixels((out / drawn).read_bytes()), pixels((ROOT / picture).read_bytes())
    assert ours.shape == theirs.shape, f"{picture}: {theirs.shape[:2]}, drawn {ours.shape[:2]}"
    apart = float(np.mean(np.abs(ours - theirs).max(axis=2) > 0.25))
    assert apart < 0.005, (
        f"{picture} is not what {doc}'s commands draw ({apart:.1%} of its pixels apart): "
        f"draw it again with them"
    )
