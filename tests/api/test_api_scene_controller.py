"""``Creature.run(scene=..., controller=...)`` takes the controller a scene starts with, as
``legdsl run --scene ... --controller`` does: for a scene with a gait table, the one its band
for the first command chooses (the API refused even that), and refuses another by name."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CREATURES

import legdsl
from legdsl.api.notes import LegdslWarning
from legdsl.lang.errors import UsageError


@pytest.fixture(scope="module")
def biped(generated: Path) -> legdsl.api.Creature:
    return legdsl.load(CREATURES / "biped.leg", generated=generated)


def test_the_controller_a_gait_table_starts_with_is_taken(biped: legdsl.api.Creature) -> None:
    # by_speed: gallop to 1.6 m/s, run from 1.4 m/s; it starts at 1.5 m/s, in the gallop's band
    with pytest.warns(LegdslWarning):  # a 0.05 s run of a 24 s scene: its later commands unseen
        run = biped.run(scene="by_speed", controller="gallop", time=0.05)
    assert run.status == "ok"


def test_another_controller_is_refused_naming_the_one_it_starts_with(
    biped: legdsl.api.Creature,
) -> None:
    with pytest.raises(
        UsageError, match="scene by_speed starts with controller gallop; leave out controller="
    ):
        biped.run(scene="by_speed", controller="run", time=0.05)


def test_a_scene_run_through_run_many_is_recorded_as_that_scene(
    biped: legdsl.api.Creature,
) -> None:
    """run_many's scene run dropped the scene's name from its info (and run.json)."""
    with pytest.warns(LegdslWarning):
        [(_, run)] = biped.run_many([{"scene": "by_speed", "time": 0.05}])
    assert run.info["scene"] == "by_speed"
