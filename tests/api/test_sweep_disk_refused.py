"""A sweep whose table the disk refuses (full, a quota, ``ulimit -f``) said only 'cannot write
OUT/sweep.csv: File too large (...), or give another place to write' (nothing before the
'or'), not how many rows were kept nor that the same command resumes, as an interrupt says."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

HOPPER = Path(__file__).resolve().parents[2] / "creatures" / "hopper.leg"
pytestmark = pytest.mark.usefixtures("hopper_modules")


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="ulimit -f in a shell")
def test_a_file_size_limit_says_what_is_kept_and_how_to_go_on(tmp_path: Path) -> None:
    out = tmp_path / "s"
    command = [sys.executable, "-m", "legdsl", "sweep", str(HOPPER), "--controller", "hop",
               "--grid", "speed=0.5:1.5:5", "--grid", "k_speed=0.04:0.1:5", "--time", "1",
               "--from", "0.5", "--jobs", "1", "--out", str(out),
               "--generated", str(tmp_path / "generated")]  # fmt: skip
    said = subprocess.run(["bash", "-c", 'ulimit -f 2; exec "$@"', "sh", *command],
                          capture_output=True, text=True, timeout=300)  # fmt: skip
    kept = len((out / "sweep.csv").read_text().splitlines()) - 1
    assert said.returncode == 2, said.stderr
    assert 0 < kept < 25
    assert said.stderr.strip().endswith(
        f"; {kept} of 25 runs are in {out / 'sweep.csv'}: raise the file-size limit (ulimit -f), "
        f"and the same command again runs the other {25 - kept}"
    ), said.stderr
    assert "Traceback" not in said.stderr and ", or give" not in said.stderr
