"""A leg whose foot's body carries a contact it does not list (a heel beside the toe):
`legdsl check` and `legdsl show` say that the leg's events and stances do not see it and how
to list it; a leg that lists every contact of its foot, or has one, gets no note."""

from __future__ import annotations

from pathlib import Path

import pytest

from legdsl.cli import main

FLAT = """
creature flat {
  planar
  gravity 9.81 m/s^2
  body trunk free { mass 10 kg  inertia 0.1 kg*m^2  initial z = 0.6 m }
  body shank on trunk via prismatic leg { length 0.5 m  mass 0.5 kg  inertia 0.01 kg*m^2 }
  body foot on shank via revolute ankle at tip {
    direction (1, 0)  length 0.1 m  mass 0.2 kg  inertia 0.001 kg*m^2
  }
  contact toe on foot at tip
  contact heel on foot at (-0.05 m, 0 m)
  leg main { joints leg, ankle  foot toe }
  ground { normal spring(k = 1e4 N/m, b = 100 N*s/m)  tangent spring(k = 1e4 N/m, b = 100 N*s/m) }
}
"""


@pytest.mark.parametrize("command", ["check", "show"])
def test_a_heel_beside_the_foot_is_noted(
    command: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    src = tmp_path / "flat.leg"
    src.write_text(FLAT, encoding="utf-8")
    assert main([command, str(src)]) == 0
    err = capsys.readouterr().err
    assert "note: flat: leg 'main' stands on 'toe' on 'foot', beside the contact(s) 'heel'" in err
    assert "touchdown(main), liftoff(main)" in err
    assert "list them: 'foot toe, heel'" in err


def test_a_heel_listed_as_a_sole_is_not_noted(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    src = tmp_path / "flat.leg"
    src.write_text(FLAT.replace("foot toe }", "foot toe, heel }"), encoding="utf-8")
    assert main(["check", str(src)]) == 0
    assert "note" not in capsys.readouterr().err


def test_one_contact_a_leg_is_not_noted(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    src = tmp_path / "flat.leg"
    src.write_text(FLAT.replace("  contact heel on foot at (-0.05 m, 0 m)\n", ""), encoding="utf-8")
    assert main(["check", str(src)]) == 0
    assert "note" not in capsys.readouterr().err


@pytest.mark.parametrize("command", ["check", "show"])
def test_contacts_with_no_ground_are_noted(
    command: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """With no ground block the feet touch nothing: check passed silently, and a run fell."""
    src = tmp_path / "flat.leg"
    without = "\n".join(line for line in FLAT.split("\n") if "ground {" not in line)
    src.write_text(without.replace("foot toe }", "foot toe, heel }"), encoding="utf-8")
    assert main([command, str(src)]) == 0
    err = capsys.readouterr().err
    assert (
        "note: flat: it has no ground block, so its contacts ('toe', 'heel') touch nothing"
    ) in err
    assert "add one: 'ground { normal spring(k = ..., b = ...)" in err


def test_a_creature_with_no_contacts_and_no_ground_is_not_noted(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    src = tmp_path / "arm.leg"
    src.write_text(
        "creature arm {\n  planar\n  body base fixed { mass 1 kg  inertia 0.1 kg*m^2 }\n"
        "  body link on base via revolute j { length 0.5 m  mass 1 kg  inertia 0.1 kg*m^2 }\n}\n",
        encoding="utf-8",
    )
    assert main(["check", str(src)]) == 0
    assert "note" not in capsys.readouterr().err
