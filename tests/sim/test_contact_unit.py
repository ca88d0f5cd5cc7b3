"""The ground contact model in isolation: eq. (6), anchors, friction, terrain."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from legdsl.ir.model import Ground, Pad, SpringDamper, Terrain
from legdsl.lang.errors import NOWHERE
from legdsl.sim.contact import PAD_LINEAR_FROM, GroundContact, _pad_energy, pad_force


def ground(
    friction: float | None = None, normal: SpringDamper | Pad | None = None, terrain=()
) -> Ground:
    return Ground(
        normal=normal or SpringDamper(1e4, 0.0),
        tangent=SpringDamper(5e3, 0.0),
        torsion=None,
        friction=friction,
        terrain=tuple(terrain),
        span=NOWHERE,
    )


@pytest.mark.parametrize("z", [-1e-4, -0.001, -0.003, -0.005, -0.0089])
def test_pad_force_is_equation_6(z: float) -> None:
    pad = Pad(k=300.0, thickness=0.01, b=0.0)
    # f_z = k_gz (k_r / (k_r + z) - 1) for z < 0
    assert pad_force(pad, -z) == pytest.approx(300.0 * (0.01 / (0.01 + z) - 1.0), rel=1e-14)


def test_pad_continues_linearly_past_the_cap_and_energy_is_its_integral() -> None:
    pad = Pad(k=300.0, thickness=0.01, b=0.0)
    cap = PAD_LINEAR_FROM * pad.thickness
    slope = pad.k * pad.thickness / (pad.thickness - cap) ** 2
    assert pad_force(pad, cap + 0.001) == pytest.approx(pad_force(pad, cap) + slope * 0.001)
    for depth in (0.002, 0.0085, 0.0095):
        n = 20000
        h = depth / n
        integral = sum(pad_force(pad, (i + 0.5) * h) for i in range(n)) * h
        assert _pad_energy(pad, depth) == pytest.approx(integral, rel=1e-6)


def test_anchor_is_set_at_each_touchdown_and_cleared_at_liftoff() -> None:
    g = GroundContact(ground(), ("toe",), planar=True)
    still = [(0.0, 0.0, 0.0)]
    events = g.update(0.0, [(0.3, 0.0, 0.05)], still)
    assert events == [] and not g.touching[0]
    events = g.update(0.1, [(0.3, 0.0, -0.001)], still)
    assert [e.kind for e in events] == ["touchdown"] and g.touching[0]
    assert g.anchor[0] == pytest.approx((0.3, 0.0, 0.0))
    # The foot is pulled back towards where it landed.
    fx, _, fz = g.force(0, (0.31, 0.0, -0.001), (0.0, 0.0, 0.0))
    assert fx == pytest.approx(-5e3 * 0.01) and fz == pytest.approx(1e4 * 0.001)
    events = g.update(0.2, [(0.35, 0.0, 0.01)], still)
    assert [e.kind for e in events] == ["liftoff"] and not g.touching[0]
    events = g.update(0.3, [(0.9, 0.0, -0.002)], still)
    assert [e.kind for e in events] == ["touchdown"]
    assert g.anchor[0] == pytest.approx((0.9, 0.0, 0.0))  # a new support period, a new anchor


def test_no_slip_by_default_and_friction_cone_when_set() -> None:
    sticky = GroundContact(ground(None), ("toe",), planar=True)
    slippy = GroundContact(ground(0.5), ("toe",), planar=True)
    for g in (sticky, slippy):
        g.update(0.0, [(0.0, 0.0, -0.001)], [(0.0, 0.0, 0.0)])
    far = (0.1, 0.0, -0.001)  # 10 cm from the anchor: 500 N tangential, 10 N normal
    assert sticky.force(0, far, (0, 0, 0))[0] == pytest.approx(-500.0)
    fx, _, fz = slippy.force(0, far, (0, 0, 0))
    assert abs(fx) == pytest.approx(0.5 * fz)
    # Outside the cone the anchor follows the foot so the spring holds exactly the cone's force.
    slippy.update(0.001, [far], [(0.0, 0.0, 0.0)])
    assert slippy.slipping[0]
    assert -5e3 * (far[0] - slippy.anchor[0][0]) == pytest.approx(-0.5 * fz)


def test_terrain_heights() -> None:
    features = [
        Terrain("step", (("height", 0.1), ("x", 2.0)), NOWHERE),
        Terrain(
            "box", (("height", 0.3), ("x0", 3.0), ("x1", 3.5), ("y0", -1.0), ("y1", 1.0)), NOWHERE
        ),
    ]
    g = GroundContact(ground(terrain=features), ("toe",), planar=False)
    assert g.height(1.0, 0.0) == 0.0
    assert g.height(2.5, 0.0) == pytest.approx(0.1)
    assert g.height(3.2, 0.0) == pytest.approx(0.3)
    assert g.height(3.2, 2.0) == pytest.approx(0.1)
    slope = GroundContact(
        ground(terrain=[Terrain("slope", (("angle", math.radians(10)),), NOWHERE)]), ("toe",), True
    )
    assert slope.height(1.0, 0.0) == pytest.approx(math.tan(math.radians(10)))
    depth, normal = slope.depth((1.0, 0.0, 0.0))
    assert depth == pytest.approx(math.sin(math.radians(10)))
    assert normal == pytest.approx((-math.sin(math.radians(10)), 0.0, math.cos(math.radians(10))))


def test_a_lifted_contact_records_no_force_while_another_touches() -> None:
    """The kangaroo lands on toe and tail and lifts them at different times: a contact that
    does not touch records zero force, even while the other one does."""
    from legdsl.pipeline.session import RunSession
    from legdsl.sim.run_loop import RunOptions

    session = RunSession.from_file(
        Path(__file__).resolve().parents[2] / "creatures" / "kangaroo.leg"
    )
    tr = session.run(options=RunOptions(duration=1.0, drop=0.1)).result.trajectory
    lifted = tr.contact == 0
    assert lifted.any() and (tr.contact == 1).any(axis=0).all()  # each contact both ways
    assert not tr.force[lifted].any()
