"""An action of a controller's own replaces the one of its name that it would otherwise take:
an included part's, its base's, or one its base got from a part (docs/language.md, "Shared
parts" and "A controller that extends another")."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import pytest

from legdsl.check.source import check_model
from legdsl.codegen.fingerprints import _clean
from legdsl.ir.controller import Controller
from legdsl.lang.errors import LegError

ROOT = Path(__file__).resolve().parents[2]
CREATURE = (ROOT / "tests" / "bad" / "ctl_dim_comparison.leg").read_text().split("controller")[0]
PART = """shared machine {
  param kp = 50 N*m/rad
  action swing(leg) { leg.hip_servo.kv = 1 N*m*s/rad }
  table {
    state FLIGHT on liftoff(main): hip_servo.kp = kp; swing(main)
    state STANCE on touchdown(main): hip_servo.kp = 0 N*m/rad
  }
}
"""
OWN_SWING = "  action swing(leg) { leg.hip_servo.kv = 3 N*m*s/rad }\n"


def _bare(c: Controller) -> Any:
    """The controller but for its name and where each part was written."""
    return _clean(dataclasses.replace(c, name="x"))


def _by_hand(tmp_path: Path) -> Controller:
    """The controller written out: the part's items with the own swing."""
    path = tmp_path / "by_hand.leg"
    path.write_text(
        CREATURE + "controller hop {\n" + PART.split("{", 1)[1].replace("1 N*m*s", "3 N*m*s")
    )
    return check_model(path).controller("hop")


def test_an_own_action_replaces_an_included_one(tmp_path: Path) -> None:
    path = tmp_path / "include.leg"
    path.write_text(
        PART + CREATURE + "controller plain {\n  include machine\n}\n"
        "controller own {\n  include machine\n" + OWN_SWING + "}\n"
    )
    model = check_model(path)  # was: action 'swing' is defined twice
    assert _bare(model.controller("own")) == _bare(_by_hand(tmp_path))
    assert _bare(model.controller("plain")) != _bare(model.controller("own"))


def test_an_extending_controller_replaces_an_action_its_base_includes(tmp_path: Path) -> None:
    path = tmp_path / "extends.leg"
    path.write_text(
        PART + CREATURE + "controller base {\n  include machine\n}\n"
        "controller derived extends base {\n" + OWN_SWING + "}\n"
        "controller further extends derived {\n  param kp = 60 N*m/rad\n}\n"
    )
    model = check_model(path)  # was: action 'swing' is defined twice
    assert _bare(model.controller("derived")) == _bare(_by_hand(tmp_path))
    assert _bare(model.controller("base")) != _bare(model.controller("derived"))
    further = model.controller("further")  # the derived's swing, kept down the chain
    assert _bare(dataclasses.replace(further, params=model.controller("derived").params)) == (
        _bare(model.controller("derived"))
    )


def test_a_bases_own_action_beside_its_include_is_kept_by_the_derived(tmp_path: Path) -> None:
    path = tmp_path / "extends.leg"
    path.write_text(
        PART + CREATURE + "controller base {\n  include machine\n" + OWN_SWING + "}\n"
        "controller derived extends base {\n  param kp = 50 N*m/rad\n}\n"
    )
    model = check_model(path)
    assert _bare(model.controller("derived")) == _bare(model.controller("base"))
    assert _bare(model.controller("base")) == _bare(_by_hand(tmp_path))


def test_an_include_of_the_derived_replaces_its_bases_own_action(tmp_path: Path) -> None:
    """The order of docs/language.md: the parts a controller includes itself beat BASE's own
    items."""
    path = tmp_path / "extends.leg"
    table = PART.replace("  action swing(leg) { leg.hip_servo.kv = 1 N*m*s/rad }\n", "")
    path.write_text(
        "shared soft {\n"
        + OWN_SWING
        + "}\n"
        + table
        + CREATURE
        + "controller base {\n  include machine\n"
        "  action swing(leg) { leg.hip_servo.kv = 7 N*m*s/rad }\n}\n"
        "controller derived extends base {\n  include soft\n}\n"
    )
    assert _bare(check_model(path).controller("derived")) == _bare(_by_hand(tmp_path))


def test_two_own_actions_of_one_name_are_still_defined_twice(tmp_path: Path) -> None:
    path = tmp_path / "twice.leg"
    path.write_text(
        PART + CREATURE + "controller own {\n  include machine\n" + OWN_SWING + OWN_SWING + "}\n"
    )
    with pytest.raises(LegError) as info:
        check_model(path)
    messages = [d.message for d in info.value.diagnostics]
    assert any(m.startswith("action 'swing' is defined twice") for m in messages), messages
