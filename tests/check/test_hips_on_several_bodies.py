"""Legs hanging from several bodies (a trunk in two halves on a spine) get a note giving each
hip from the centre of mass: `legdsl show` lists them in the root body's frame, whose origin
is then the front half's, where a rear hip placed from the wrong origin looked right."""

from __future__ import annotations

import re
from pathlib import Path

from conftest import ROOT

from legdsl.check.leg_notes import leg_contact_notes
from legdsl.check.source import check_model

SPINE = ROOT / "tests" / "good" / "outside" / "spine_quadruped.leg"


def _hips(note: str) -> dict[str, tuple[float, float]]:
    found = re.findall(r"(\w+) on '\w+' at \((-?[\d.]+), (-?[\d.]+)\) m", note)
    return {leg: (float(x), float(y)) for leg, x, y in found}


def test_the_hips_of_a_spine_are_given_from_the_centre_of_mass() -> None:
    (note,) = leg_contact_notes(check_model(SPINE))
    assert "centre of mass is at (-0.225, 0.000, -0.182) m in the root body's frame" in note
    hips = _hips(note)
    assert hips["fl"] == (0.39, 0.12) and hips["rr"] == (-0.39, -0.12)


def test_a_rear_hip_placed_from_the_front_halfs_centre_shows(tmp_path: Path) -> None:
    """The hips 0.165 m behind the spine, meant 0.165 m behind the rear half's centre: the
    note puts them 0.22 m behind the centre of mass and the front ones 0.33 m ahead (this
    creature bounded backwards)."""
    text = SPINE.read_text(encoding="utf-8").replace("../../../", f"{ROOT}/")
    wrong = tmp_path / "wrong.leg"
    wrong.write_text(text.replace("BODY = rear, HIP = (-0.39 m", "BODY = rear, HIP = (-0.165 m"))
    (note,) = leg_contact_notes(check_model(wrong))
    hips = _hips(note)
    assert hips["fl"][0] == 0.334 and hips["rl"][0] == -0.221


def test_legs_on_one_body_get_no_note() -> None:
    assert leg_contact_notes(check_model(ROOT / "creatures" / "quadruped.leg")) == []
