"""A control law that fails in a ``--scale L`` run is told in the scaled creature's time and
values, as the run of the file ``legdsl scale --by L`` writes tells them (docs/scaling.md).

Reported from outside: ``--scale 4`` on a biped whose hip gain a fault input drove negative at
1 s was told 'at t = 0.5000 s: it sets servo_l.kp = -150 N*m/rad' (the unscaled model's time
and value) where the run said 1.0 s and the scaled file's run -3.84e4 N*m/rad."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.cli import main

ROW = "state COMPRESSION on active.rate < 0:       servo_pitch(active, body, 0 deg, kp, kv)"
CASES = {
    "negative": "leg_spring.k = 3000 N/m - 10000 N/m * com.z / 1 m",
    "sqrt": "hip_motor.force = 0.001 N*m*s/m * sqrt(2 * g * (height - com.z) - 20 m^2/s^2)",
}


def _failed(capsys: pytest.CaptureFixture[str], argv: list[str]) -> str:
    assert main(argv) == 3
    (line,) = [x for x in capsys.readouterr().err.splitlines() if "control law failed" in x]
    return line.split(": the control law failed ", 1)[1]


@pytest.mark.parametrize("backend", ["c", "python"])
@pytest.mark.parametrize("case", sorted(CASES))
def test_a_scaled_runs_failing_law_is_told_as_the_scaled_files(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, case: str, backend: str
) -> None:
    text = (CREATURES / "hopper.leg").read_text()
    leg = tmp_path / "hopper.leg"
    leg.write_text(text.replace(ROW, f"{ROW}; {CASES[case]}"))
    big = tmp_path / "hopper_x4.leg"
    assert main(["scale", str(leg), "--by", "4", "-o", str(big)]) == 0
    common = ["--controller", "hop", "--time", "2", "--backend", backend,
              "--generated", str(tmp_path / "gen")]  # fmt: skip
    scaled = _failed(
        capsys, ["run", str(leg), "--scale", "4", *common, "--out", str(tmp_path / "a")]
    )
    told = _failed(capsys, ["run", str(big), *common, "--out", str(tmp_path / "b")])
    assert scaled.startswith("in state COMPRESSION at t = 0.3600 s: ")  # 0.18 s * sqrt(4)
    if case == "negative":
        assert scaled == told  # its value -7.442e+04 N/m, the scaled file's
        assert "it sets leg_spring.k = -7.442e+04 N/m" in scaled
    else:  # the values it read are the scaled creature's; the operation's own, the file's
        read = re.compile(r"; it read (.*)$")
        assert (
            read.search(scaled)[1] == read.search(told)[1] == "com.z = 3.06 m, input height = 4 m"
        )
        assert "sqrt(-15.39) has no real value (its operands are the unscaled file's numbers)" in (
            scaled
        )
