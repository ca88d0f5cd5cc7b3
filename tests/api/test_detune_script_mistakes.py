"""docs/scripts/detune.py (docs/api.md, "Tuning from detuned gains") told a mistake in its
options with a traceback: ``--times nosuch=2`` a KeyError, ``--times kp=nan`` "Invalid literal
for Fraction". Each is a sentence now, exit status 2, and nothing is written."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "docs" / "scripts" / "detune.py"
KANGAROO = ROOT / "creatures" / "kangaroo.leg"


@pytest.mark.parametrize(
    ("times", "said"),
    [
        (["nosuch=2"], "--times nosuch: not a parameter of controller 'hop'"),
        (["kp=nan"], "the factor 'nan' is not a number"),
        (["kp=1/0"], "the factor '1/0' is not a number"),
        (["kp"], "write NAME=FACTOR"),
        (["kp=2", "kp=3"], "--times kp: given twice"),
    ],
)
def test_a_mistake_in_times_is_a_sentence(tmp_path: Path, times: list[str], said: str) -> None:
    out = tmp_path / "detuned.leg"
    given = [a for t in times for a in ("--times", t)]
    done = subprocess.run(
        [sys.executable, str(SCRIPT), str(KANGAROO), "--controller", "hop", *given, "-o", str(out)],
        capture_output=True, text=True, cwd=tmp_path,
    )  # fmt: skip
    assert done.returncode == 2, done.stderr
    assert said in done.stderr
    assert "Traceback" not in done.stderr
    assert not out.exists()


def test_an_unknown_controller_is_named(tmp_path: Path) -> None:
    done = subprocess.run(
        [sys.executable, str(SCRIPT), str(KANGAROO), "--controller", "nosuch", "--times",
         "kp=2", "-o", str(tmp_path / "d.leg")], capture_output=True, text=True, cwd=tmp_path,
    )  # fmt: skip
    assert done.returncode == 2
    assert "has no such controller (it has hop, jump)" in done.stderr
