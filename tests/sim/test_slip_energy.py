"""A contact that slides fast on a light touch holds no energy that no force stored.

Reported from outside: a passive 3D creature's recorded ``elastic`` energy leapt from 0.27 J to
11.16 J in one sample (total 27.5 J -> 36.9 J), when a contact in no leg's foot first touched.
The energy was in another contact's tangential ground spring: that foot slid at 4.8 m/s under
a normal force of about 5 N, and the slip rule put its anchor where spring and damper together
held the cone's force. The damper alone asked 100 N*s/m x 4.8 m/s = 480 N, so the anchor went
4.8 cm *ahead* of the foot and the spring, pushing against the damper, "held" 11 J that no
force had done work to store (the force on the foot stayed inside the 4 N cone). The anchor
now follows the foot, straight towards it, only as far as makes the spring alone hold the
cone's force: it holds at most (mu fn)^2 / (2 k), and slip only takes energy away."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from runtime_helpers import needs_c_compiler

from legdsl.cli import main
from legdsl.ir.model import Ground, SpringDamper
from legdsl.lang.errors import NOWHERE
from legdsl.sim.contact import GroundContact
from legdsl.sim.trajectory import Trajectory

# A passive sled whose three contacts are in no leg (no leg's foot), dropped 1 cm onto the
# ground while it slides at 4.1 m/s: nothing in it makes energy.
SLED = """\
creature sled {
  spatial
  body hull free {
    mass 0.5 kg  inertia (0.002, 0.004, 0.005) kg*m^2
    initial x = 0 m, y = 0 m, z = 0.03 m
    velocity vx = 4 m/s, vy = 1 m/s
  }
  contact nose on hull at (0.1 m, 0 m, -0.02 m)
  contact port on hull at (-0.05 m, 0.06 m, -0.02 m)
  contact starboard on hull at (-0.05 m, -0.06 m, -0.02 m)
  ground {
    normal spring(k = 2e4 N/m, b = 200 N*s/m)
    tangent spring(k = 1e4 N/m, b = 100 N*s/m)
    friction 0.8
  }
}
"""


def _ground(planar: bool) -> GroundContact:
    g = Ground(
        normal=SpringDamper(2e4, 200.0),
        tangent=SpringDamper(1e4, 100.0),
        torsion=None,
        friction=0.8,
        terrain=(),
        span=NOWHERE,
    )
    return GroundContact(g, ("toe",), planar=planar)


def _held(g: GroundContact, p: tuple[float, float, float]) -> float:
    a = g.anchor[0]
    return 0.5 * 1e4 * ((p[0] - a[0]) ** 2 + (p[1] - a[1]) ** 2)


@pytest.mark.parametrize("planar", [True, False])
def test_a_fast_slide_moves_the_anchor_only_towards_the_foot(planar: bool) -> None:
    g = _ground(planar)
    g.update(0.0, [(0.0, 0.0, -1e-4)], [(4.8, 0.0, 0.0)])  # touches down, 2 N of spring
    assert g.touching[0] and g.anchor[0] == pytest.approx((0.0, 0.0, 0.0))
    p, v = (0.002, 0.0, -1e-4), (4.8, 0.0, 0.0)  # one step on, still sliding at 4.8 m/s
    before = _held(g, p)
    fn = g.force(0, p, v)[2]
    g.update(0.0004, [p], [v])
    assert g.slipping[0]
    cone = 0.8 * fn
    # the anchor moved towards the foot (it trails it), and the spring holds the cone's force
    assert 0.0 < g.anchor[0][0] < p[0]
    assert 1e4 * (p[0] - g.anchor[0][0]) == pytest.approx(cone, rel=1e-12)
    assert _held(g, p) == pytest.approx(cone**2 / 2e4, rel=1e-12) and _held(g, p) < before
    # the force on the foot is the cone's, against the slide
    fx = g.force(0, p, v)[0]
    assert fx == pytest.approx(-cone, rel=1e-12)


def test_a_spring_within_the_cone_keeps_its_anchor_while_the_damper_slides() -> None:
    g = _ground(planar=False)
    g.update(0.0, [(0.0, 0.0, -1e-3)], [(1.0, 0.0, 0.0)])
    p, v = (1e-4, 0.0, -1e-3), (1.0, 0.0, 0.0)  # the spring 1 N, its damper 100 N
    g.update(0.0004, [p], [v])
    assert g.slipping[0]  # the force is held to the cone ...
    assert g.anchor[0] == pytest.approx((0.0, 0.0, 0.0))  # ... and the spring keeps its anchor


def _run(tmp_path: Path, backend: str) -> Trajectory:
    leg = tmp_path / "sled.leg"
    leg.write_text(SLED, encoding="utf-8")
    out = tmp_path / f"run_{backend}"
    code = main(["run", str(leg), "--time", "0.6", "--backend", backend,
                 "--generated", str(tmp_path / "gen"), "--out", str(out)])  # fmt: skip
    assert code == 0
    return Trajectory.load(out)


@pytest.mark.parametrize("backend", ["python", pytest.param("c", marks=needs_c_compiler)])
def test_a_passive_sled_sliding_onto_the_ground_never_gains_energy(
    tmp_path: Path, backend: str
) -> None:
    tr = _run(tmp_path, backend)
    total = tr.kinetic + tr.potential + tr.elastic
    start = total[0]
    assert math.isclose(start, 0.5 * 0.5 * (4**2 + 1**2) + 0.5 * 9.81 * 0.03, rel_tol=1e-2)
    # the touchdowns and the slide only take energy away (it read 24.1 J, 5.5 times the start)
    assert np.all(np.diff(total) <= 1e-9 * start)
    # what the ground's springs hold is the normal springs' weight and the cones' little
    # (it read 20.5 J: the tangential springs pushing against their dampers)
    assert tr.elastic.max() < 0.02


@needs_c_compiler
def test_the_backends_slide_alike(tmp_path: Path) -> None:
    py, c = _run(tmp_path, "python"), _run(tmp_path, "c")
    for key in ("q", "v", "elastic", "force"):
        assert np.array_equal(getattr(py, key), getattr(c, key)), key
