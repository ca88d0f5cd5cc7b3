"""A state whose event can never hold is noted by `legdsl check` and `show`: the machine stays
in the state before it for good, and nothing said so (an outside user's `on trunk.z > trunk.z`
and `touchdown(main) and liftoff(main)` ran with the machine in one state all run)."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.check.event_notes import never_entered
from legdsl.check.source import check_file, check_model
from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]

CREATURE = """\
creature c {
  planar
  body trunk free { mass 1 kg  inertia 0.01 kg*m^2  initial x = 0 m, z = 1 m }
  body leg on trunk via revolute hip { mass 1 kg  inertia 0.01 kg*m^2  length 0.5 m }
  contact toe on leg at tip
  leg main { joints hip  foot toe }
  actuator hip_servo on hip servo(kp = 10 N*m/rad)
  ground { normal spring(k = 2e4 N/m, b = 200 N*s/m)  tangent spring(k = 1e4 N/m, b = 100 N*s/m) }
}
controller hold {
  signal h = trunk.z
  table {
    state A on time_in_state > 0.1 s: hip_servo.setpoint = 0 deg
%s
  }
}
"""

NEVER = [
    "trunk.z > h + 0 m",  # its sides cancel once the signal is written out
    "touchdown(main) and liftoff(main)",
    "com.z > 1 m and 0.5 m > com.z",  # ranges that do not meet, one written the other way
    "not (com.z > 1 m or com.z < 2 m)",
    "2 * com.z < 2 m and com.z >= 1 m",  # one part, scaled
]
CAN = [
    "com.z > 1 m and com.z < 2 m",
    "2 * com.z - com.z - com.z == 0 m",  # always true: entered at once, not stuck
    "time_in_state > 0.1 s or trunk.z < trunk.z",
    "touchdown(main) or liftoff(main)",
    "com.z >= 1 m and com.z <= 1 m",
    "touchdown(main) and com.z > 1 m",
]


def notes(tmp_path: Path, events: list[str]) -> list[str]:
    rows = "\n".join(
        f"    state S{k} on {event}: hip_servo.setpoint = 0 deg" for k, event in enumerate(events)
    )
    path = tmp_path / "c.leg"
    path.write_text(CREATURE % rows, encoding="utf-8")
    return never_entered(check_model(path))


@pytest.mark.parametrize("event", NEVER)
def test_an_event_that_never_holds_is_noted(event: str, tmp_path: Path) -> None:
    (note,) = notes(tmp_path, [event])
    assert note.startswith(f"{tmp_path / 'c.leg'}:14:5: controller hold: state S0's event ")
    assert note.endswith("is false whatever the creature's state, so the machine never leaves A; "
                         "give it an event that can hold")  # fmt: skip


def test_events_that_can_hold_are_not_noted(tmp_path: Path) -> None:
    assert notes(tmp_path, CAN) == []


def test_no_shipped_or_outside_controller_is_noted() -> None:
    files = [*(ROOT / "creatures").glob("*.leg"), *(ROOT / "tests/good/outside").glob("*.leg")]
    assert len(files) > 30
    for path in files:
        for model in check_file(path):
            assert never_entered(model) == [], path


def test_legdsl_check_prints_the_note(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    notes(tmp_path, NEVER[:1])
    assert main(["check", str(tmp_path / "c.leg")]) == 0
    assert "legdsl: note: " in capsys.readouterr().err
