"""``-o -`` for a directory a command writes its files into: it made a directory named '-'
(``legdsl run hopper.leg -o -`` said "written to -/", exit 0), where ``export -o -`` writes
standard output and ``plot -o -`` is refused. Refused now, with a caret, before any work."""

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
        ("run", HOPPER, "--time", "0.2", "-o", "-"),
        ("compile", HOPPER, "-o", "-"),
        (
            "sweep",
            HOPPER,
            "--controller",
            "hop",
            "--grid",
            "speed=0.5,1",
            "--time",
            "0.3",
            "--from",
            "0.1",
            "--out",
            "-",
        ),
        (
            "tune",
            HOPPER,
            "--controller",
            "hop",
            "--param",
            "kp=100:200",
            "--speeds",
            "1",
            "--time",
            "0.3",
            "--from",
            "0.1",
            "--out",
            "-",
        ),
    ],  # fmt: skip
    ids=["run", "compile", "sweep", "tune"],
)
def test_a_directory_output_named_dash_is_refused(tmp_path: Path, words: tuple[str, ...]) -> None:
    proc = subprocess.run([sys.executable, "-m", "legdsl", *words], cwd=tmp_path, env=ENV,
                          capture_output=True, text=True, timeout=120)  # fmt: skip
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.splitlines() == [
        "legdsl: --out -: a directory of files cannot go to standard output; give a directory "
        "name (./- for a directory named '-')",
        "    --out -",
        "          ^",
    ]
    assert list(tmp_path.iterdir()) == []


def test_a_file_in_a_directory_named_dash_is_still_written(tmp_path: Path) -> None:
    """Only the directory itself named '-' is refused: ``-o -/x.xml`` (--output=-/x.xml) is a file in one."""
    proc = subprocess.run([sys.executable, "-m", "legdsl", "export", HOPPER, "--output=-/x.xml"],
                          cwd=tmp_path, env=ENV, capture_output=True, text=True, timeout=120)  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "-" / "x.xml").is_file()
