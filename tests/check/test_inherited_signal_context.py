"""A signal taken from a base controller reads the extending controller's creature, so a
mistake in it (a body the creature lacks) names the controller it is checked in and the one
that wrote it, as every other item taken from a base does."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from legdsl.check.source import check_model
from legdsl.lang.errors import LegError

ROOT = Path(__file__).resolve().parents[2]
QUADRUPED = ROOT / "creatures" / "quadruped.leg"


def test_a_base_signals_mistake_names_the_controllers(tmp_path: Path) -> None:
    """It said only "quadruped.leg:202:24: error: creature 'torsoq' has no body 'trunk' (its
    bodies: ...)", where the actions' mistakes say in which controller."""
    shutil.copy(QUADRUPED, tmp_path / "quadruped.leg")
    text = QUADRUPED.read_text()
    creature = text[text.index("creature quadruped {") :]
    creature = creature[: creature.index("\n}\n") + 3]
    creature = creature.replace("creature quadruped", "creature torsoq").replace("trunk", "torso")
    leg = tmp_path / "torsoq.leg"
    leg.write_text(f'use "quadruped.leg"\n\n{creature}\ncontroller trot extends trot {{ }}\n')
    with pytest.raises(LegError) as e:
        check_model(leg)
    said = e.value.render()
    signal_lines = [
        line
        for line in said.splitlines()
        if "error: creature 'torsoq' has no body 'trunk'" in line
        and "signal"
        in (tmp_path / "quadruped.leg").read_text().splitlines()[int(line.split(":")[1]) - 1]
    ]
    assert signal_lines, said
    for line in signal_lines:
        assert "(in controller 'trot', from " in line, line
