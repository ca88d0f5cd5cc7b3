"""A standard output that refuses what is written (``> /dev/full``) was told twice: "cannot
write standard output" once where the command failed and once more at the final flush."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
HOPPER = str(ROOT / "creatures" / "hopper.leg")
ENV = dict(os.environ, PYTHONPATH=str(ROOT / "src"))


@pytest.mark.parametrize(
    "words",
    [
        ("show", HOPPER),
        ("check", HOPPER),
        ("export", HOPPER, "--format", "mjcf", "-o", "-"),
        ("run", "--help"),
    ],  # fmt: skip
    ids=["show", "check", "export", "help"],
)
def test_a_full_standard_output_is_told_once(tmp_path: Path, words: tuple[str, ...]) -> None:
    with open("/dev/full", "w") as full:
        proc = subprocess.run([sys.executable, "-m", "legdsl", *words], cwd=tmp_path, env=ENV,
                              stdout=full, stderr=subprocess.PIPE, text=True, timeout=120)  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("legdsl: cannot write standard output"), lines
