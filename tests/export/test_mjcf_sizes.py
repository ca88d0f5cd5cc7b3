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


BRICK = """creature brick {
  spatial
  body block free {
    mass 4 kg
    inertia (0.05 kg*m^2, 0.07 kg*m^2, 0.09 kg*m^2)
    initial z = 0.15 m
    shape box(0.3 m, 0.2 m, 0.1 m)
  }
  contact c1 on block at (0.15 m, 0.1 m, -0.05 m)
  contact c2 on block at (0.15 m, -0.1 m, -0.05 m)
  contact c3 on block at (-0.15 m, 0.1 m, -0.05 m)
  contact c4 on block at (-0.15 m, -0.1 m, -0.05 m)
  ground {
    normal spring(k = 2e4 N/m, b = 200 N*s/m)
    tangent spring(k = 1e4 N/m, b = 150 N*s/m)
    friction none
  }
}
"""


def test_a_small_creature_without_links_gets_small_contact_spheres(tmp_path: Path) -> None:
    """A 3 mm brick (no link lengths) kept 5 mm spheres: MuJoCo's contact force, on their
    surface 5 mm below each corner, turned it 29 degrees off legdsl's run. Its spheres are a
    fiftieth of its size (the diagonal of its 3 x 2 x 1 mm box), as a linked creature's are of
    its longest link, and the floor is that far below legdsl's."""
    (tmp_path / "brick.leg").write_text(BRICK)
    small = tmp_path / "small.leg"
    assert main(["scale", str(tmp_path / "brick.leg"), "--by", "0.01", "-o", str(small)]) == 0
    mj = mujoco.MjModel.from_xml_string(model_to_mjcf(check_model(small)))
    diagonal = float(np.linalg.norm([0.003, 0.002, 0.001]))
    radius = mj.geom("c1").size[0]
    assert radius == pytest.approx(0.02 * diagonal)
    assert mj.geom("floor").pos[2] == pytest.approx(-radius)
