"""``fall_tilt="60"``, a text without its unit, was read as ``--fall-tilt 60`` is (degrees)
while ``fall_tilt=60`` is radians: ``"1.0"`` meant as a radian stopped a run at a one-degree
tilt. A bare number in a text is refused now, saying which unit each form is in."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import ROOT

import legdsl
from legdsl.lang.errors import UsageError

POGO = ROOT / "tests" / "good" / "outside" / "insect_pogo.leg"


@pytest.fixture(scope="module")
def pogo(generated: Path) -> legdsl.api.Creature:
    return legdsl.load(POGO, generated=generated)


def test_a_tilt_text_without_unit_is_refused(pogo) -> None:
    with pytest.raises(UsageError, match=r"fall_tilt='1.0' has no unit.*'1.0 deg'"):
        pogo.run(controller="hop", time=0.01, fall_tilt="1.0")


def test_a_tilt_with_its_unit_or_in_radians_is_taken(pogo) -> None:
    tilt = pogo.run(controller="hop", time=0.01, fall_tilt="30 deg").info["options"]["fall_tilt"]
    assert tilt == pytest.approx(0.5235987755982988)
    assert pogo.run(controller="hop", time=0.01, fall_tilt=1.0).info["options"]["fall_tilt"] == 1
