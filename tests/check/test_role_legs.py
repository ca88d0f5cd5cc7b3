"""A ``roles`` line naming a leg the creature lacks: told with the creature's legs, and for a
line taken from another controller (``extends``), once, with the line to write instead."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from legdsl.check.source import check_model
from legdsl.lang.errors import LegError

ROOT = Path(__file__).resolve().parents[2]
QUADRUPED = ROOT / "creatures" / "quadruped.leg"
NEW_NAMES = {"fl": "lf", "fr": "rf", "rl": "lh", "rr": "rh"}


def _renamed(tmp_path: Path, controllers: str) -> Path:
    """The quadruped as creature 'renamed', its legs lf, rf, lh, rh, using quadruped.leg."""
    shutil.copy(QUADRUPED, tmp_path / "quadruped.leg")
    text = QUADRUPED.read_text()
    creature = text[text.index("creature quadruped {") :]
    creature = creature[: creature.index("\n}\n") + 3].replace(
        "creature quadruped", "creature renamed"
    )
    creature = re.sub(
        r"instance (fl|fr|rl|rr) = leg\(S = \1",
        lambda m: f"instance {NEW_NAMES[m[1]]} = leg(S = {NEW_NAMES[m[1]]}",
        creature,
    )
    leg = tmp_path / "renamed.leg"
    leg.write_text('use "quadruped.leg"\n\n' + creature + "\n" + controllers)
    return leg


def test_roles_taken_from_a_base_name_the_creatures_legs_and_the_line_to_write(
    tmp_path: Path,
) -> None:
    """It gave 4 errors per controller ('unknown leg 'fl'; roles are bound to legs declared
    with 'leg NAME { ... }''), naming neither the creature's legs nor the fix."""
    leg = _renamed(tmp_path, "controller trot extends trot { }\n")
    with pytest.raises(LegError) as e:
        check_model(leg)
    text = e.value.render()
    assert text.count("error:") == 1, text
    assert (
        "error: unknown legs 'fl', 'rr', 'fr', 'rl'; roles are bound to legs declared with "
        "'leg NAME { ... }' (creature 'renamed' has lf, rf, lh, rh), and this 'roles' line is "
        f"taken from another controller's: give controller 'trot' ({leg}:"
    ) in text, text
    assert (
        "a line of its own with its legs, 'roles active = (LEG, LEG), idle = (LEG, LEG)' (it "
        "replaces the line taken) (in controller 'trot', from controller 'trot' of "
    ) in text, text


def test_the_line_it_asks_for_is_the_fix(tmp_path: Path) -> None:
    leg = _renamed(
        tmp_path, "controller trot extends trot { roles active = (lf, rh), idle = (rf, lh) }\n"
    )
    assert dict(check_model(leg).controller("trot").bindings[0]) == {
        "active": ("lf", "rh"),
        "idle": ("rf", "lh"),
    }


def test_a_controllers_own_roles_name_each_unknown_leg_with_the_creatures_legs(
    tmp_path: Path,
) -> None:
    leg = _renamed(
        tmp_path, "controller trot extends trot { roles active = (fl, rh), idle = (rf, lh) }\n"
    )
    with pytest.raises(LegError) as e:
        check_model(leg)
    text = e.value.render()
    assert text.count("error:") == 1, text
    assert (
        "error: unknown leg 'fl'; roles are bound to legs declared with 'leg NAME { ... }' "
        "(creature 'renamed' has lf, rf, lh, rh)\n"
    ) in text, text
