"""``legdsl show`` lists a scene with a gait table by its bands: it listed the first band's
controller alone ('by_speed: trot for 24 s'), as if the scene only trotted."""

from __future__ import annotations

from conftest import CREATURES

from legdsl.check.source import check_model
from legdsl.ir.describe import describe_model


def test_a_gait_by_speed_scene_shows_every_band_in_the_inputs_unit() -> None:
    model = check_model(CREATURES / "quadruped.leg")
    (scene,) = [s for s in model.scenes if s.bands]
    (line,) = [x for x in describe_model(model).splitlines() if x.startswith(f"  {scene.name}:")]
    bands = "; ".join(b.text("m/s") for b in scene.bands)
    assert len(scene.bands) > 1 and f"gait by speed {{ {bands} }}" in line
    assert "bound from 2.4 m/s to 3.5 m/s" in line
