"""What the MJCF export sizes from the creature rather than from the terrain: MuJoCo's view
scale (``<statistic>``) and the length of a step's box."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT

from legdsl.check.source import check_model
from legdsl.cli import main
from legdsl.export.mjcf import model_to_mjcf

mujoco = pytest.importorskip("mujoco")

HOPPER = ROOT / "creatures" / "hopper.leg"


def stepped_hopper(tmp_path: Path, factor: float) -> tuple[object, float]:
    """The hopper scaled by ``factor`` with a step 2 hopper-lengths ahead, loaded in MuJoCo,
    and the creature's height (its highest body origin to its lowest contact)."""
    scaled = tmp_path / "scaled.leg"
    assert main(["scale", str(HOPPER), "--by", str(factor), "-o", str(scaled)]) == 0
    step = f"    friction none\n    terrain step(x = {2 * factor} m, height = {0.04 * factor} m)"
    stepped = tmp_path / "stepped.leg"
    stepped.write_text(scaled.read_text().replace("    friction none", step, 1))
    mj = mujoco.MjModel.from_xml_string(model_to_mjcf(check_model(stepped), pads=False))
    data = mujoco.MjData(mj)
    mujoco.mj_kinematics(mj, data)
    points = np.vstack([data.xpos[1:], data.site_xpos])
    return mj, float(np.ptp(points[:, 2]))


def test_a_step_does_not_clip_a_small_creature_from_view(tmp_path: Path) -> None:
    """A 5 cm hopper on a step: MuJoCo's extent counted the step's 100 m box (141 m), its near
    clipping plane (znear x extent) was 1.41 m away, and every view of the hopper was black."""
    mj, height = stepped_hopper(tmp_path, 0.05)
    near = mj.vis.map.znear * mj.stat.extent
    assert mj.stat.extent < 3 * height
    assert near < 0.05 * height
    assert abs(mj.stat.center[0]) < height  # the viewer looks at the creature, not the step


def test_a_large_creatures_step_is_long_for_it(tmp_path: Path) -> None:
    """A step runs 100 m towards +x; a 40 m hopper's ran 2.5 of its heights: it is at least
    50 of the creature's sizes."""
    mj, height = stepped_hopper(tmp_path, 50.0)
    half_length, half_width = mj.geom("terrain0").size[:2]
    assert half_length >= 25 * height and half_width >= 25 * height
