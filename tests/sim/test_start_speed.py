"""A start velocity past the divergence rule's limit is told as the file's, before any step.

Reported from outside: a root started at ``velocity x = 1200 m/s`` was told 'diverged at
t = 0 ... the state grew without bound; try a smaller step (--dt ...) or --integrator rk4',
and again after both: nothing grew, the speed is the file's."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from runtime_helpers import needs_c_compiler

from legdsl.cli import main

PUSHED = """\
creature pushed {
  planar
  body trunk free {
    mass 5 kg  inertia 0.1 kg*m^2
    initial x = 0 m, z = 1 m, pitch = 0 deg
    velocity x = 1200 m/s
  }
  body leg1 on trunk via revolute hip {
    length 0.5 m  com 0.25 m  mass 0.5 kg  inertia 0.01 kg*m^2
  }
  contact toe on leg1 at tip
  actuator hip_servo on hip servo(kp = 50 N*m/rad, kv = 2 N*m*s/rad)
  ground { normal spring(k = 2e4 N/m, b = 200 N*s/m)  tangent spring(k = 1e4 N/m, b = 100 N*s/m) }
}
"""
CAUSE = (
    "Likely cause: nothing grew without bound: the creature starts at this speed, the start "
    "velocity its file gives ({given}), which no step or integrator changes; the limit is the "
    "divergence rule's for a creature of its size (docs/runtime.md#divergence-and-falls): give "
    "its `velocity` a speed under {bound}. State: "
)


@needs_c_compiler
@pytest.mark.parametrize(
    ("more", "given", "bound"),
    [
        ([], "x = 1200 m/s", "1000 m/s"),
        (["--dt", "0.01ms", "--integrator", "rk4", "--backend", "python"], "x = 1200 m/s",
         "1000 m/s"),
        (["--scale", "4"], "x = 2400 m/s, as --scale 4 makes the file's 1200 m/s",
         "500 m/s there (1000 m/s scaled)"),
    ],
)  # fmt: skip
def test_a_start_speed_past_the_limit_is_told_as_the_files(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], more: list[str], given: str, bound: str
) -> None:
    leg = tmp_path / "push.leg"
    leg.write_text(PUSHED, encoding="utf-8")
    out = tmp_path / "run"
    argv = ["run", str(leg), "--time", "0.2", "--generated", str(tmp_path / "gen"),
            "--out", str(out), *more]  # fmt: skip
    assert main(argv) == 3
    err = capsys.readouterr().err
    assert CAUSE.format(given=given, bound=bound) in err
    assert "smaller step" not in err and "rk4" not in err
    info = json.loads((out / "run.json").read_text())
    assert info["status"] == "diverged" and info["ended_at"] == 0.0 and info["steps"] == 0
