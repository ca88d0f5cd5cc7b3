"""Shape meshes: closed, outward-facing, the right size and place; side outlines."""

from __future__ import annotations

import math

import numpy as np
import pytest

from legdsl.export.shapes import SEGMENTS, body_mesh, side_outline
from legdsl.ir.model import Body, Shape
from legdsl.lang.errors import Span

SPAN = Span("test.leg", 1, 1, 1, 2)


def body(shape: Shape, length: float | None = None, direction=(0.0, 0.0, -1.0)) -> Body:
    eye = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    return Body(
        "b", None, "j", 1.0, (0.0, 0.0, 0.0), eye, length, direction, shape, "#ff0000", SPAN
    )


def volume(mesh) -> float:
    """Signed volume by the divergence theorem: positive only if every triangle faces outwards."""
    tri = mesh.positions[mesh.indices].astype(float)
    return float(np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6)


def polygon_area(r: float) -> float:
    """Area of the regular SEGMENTS-gon inscribed in a circle of radius r."""
    return 0.5 * SEGMENTS * r * r * math.sin(2 * math.pi / SEGMENTS)


CASES = [
    ("box", body(Shape("box", (("x", 0.4), ("y", 0.2), ("z", 0.1)), (0.1, 0.0, 0.05))), 0.4 * 0.2 * 0.1),
    ("cylinder", body(Shape("cylinder", (("r", 0.05),)), 0.5), polygon_area(0.05) * 0.5),
    (
        "frustum",
        body(Shape("frustum", (("r0", 0.07), ("r1", 0.03))), 0.3, (0.6, 0.0, -0.8)),
        # a pyramid frustum on regular polygons: h/3 (A0 + A1 + sqrt(A0 A1))
        0.3 / 3 * (polygon_area(0.07) + polygon_area(0.03) + math.sqrt(polygon_area(0.07) * polygon_area(0.03))),
    ),
    ("sphere", body(Shape("sphere", (("r", 0.1),), (0.0, 0.2, 0.0))), 4 / 3 * math.pi * 0.1**3),
    (
        "capsule",
        body(Shape("capsule", (("r", 0.04),)), 0.4, (1.0, 0.0, 0.0)),
        math.pi * 0.04**2 * 0.4 + 4 / 3 * math.pi * 0.04**3,
    ),
]  # fmt: skip


@pytest.mark.parametrize(("name", "b", "expected"), CASES, ids=[c[0] for c in CASES])
def test_mesh_encloses_the_shape_volume_facing_outwards(
    name: str, b: Body, expected: float
) -> None:
    mesh = body_mesh(b)
    assert mesh.positions.dtype == np.float32 and mesh.indices.dtype == np.uint32
    assert np.allclose(np.linalg.norm(mesh.normals, axis=1), 1.0, atol=1e-5)
    # Tessellated curved surfaces lose a little volume; a flipped triangle would cost far more.
    assert volume(mesh) == pytest.approx(
        expected, rel=0.03 if name in ("sphere", "capsule") else 1e-4
    )
    # Each triangle's winding agrees with its vertex normals.
    tri = mesh.positions[mesh.indices].astype(float)
    face = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    big = np.linalg.norm(face, axis=1) > 1e-12
    assert np.all(np.einsum("ij,ij->i", face, mesh.normals[mesh.indices].mean(axis=1))[big] > 0)


def test_link_shapes_run_from_the_origin_to_the_tip() -> None:
    b = body(Shape("frustum", (("r0", 0.07), ("r1", 0.03))), 0.3, (0.6, 0.0, -0.8))
    p = body_mesh(b).positions.astype(float)
    along = p @ np.array([0.6, 0.0, -0.8])
    assert along.min() == pytest.approx(0.0, abs=1e-6)
    assert along.max() == pytest.approx(0.3, abs=1e-6)


def test_box_and_sphere_sit_at_their_centre() -> None:
    lo, hi = body_mesh(CASES[0][1]).bounds
    assert np.allclose(lo, [-0.1, -0.1, 0.0]) and np.allclose(hi, [0.3, 0.1, 0.1])
    lo, hi = body_mesh(CASES[3][1]).bounds
    assert np.allclose((lo + hi) / 2, [0.0, 0.2, 0.0], atol=1e-6)


def test_a_link_shape_without_length_is_a_sphere_at_the_origin() -> None:
    mesh = body_mesh(body(Shape("cylinder", (("r", 0.05),)), None))
    assert volume(mesh) == pytest.approx(4 / 3 * math.pi * 0.05**3, rel=0.03)
    assert np.allclose(mesh.positions.mean(axis=0), 0.0, atol=1e-3)


def shoelace(poly: np.ndarray) -> float:
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def test_side_outlines() -> None:
    box = side_outline(CASES[0][1])
    assert shoelace(box) == pytest.approx(0.4 * 0.1)
    assert np.allclose(box.mean(axis=0), [0.1, 0.05])
    frustum = body(Shape("frustum", (("r0", 0.07), ("r1", 0.03))), 0.3, (0.6, 0.0, -0.8))
    assert shoelace(side_outline(frustum)) == pytest.approx((0.07 + 0.03) * 0.3)
    capsule = side_outline(CASES[4][1])
    assert shoelace(capsule) == pytest.approx(0.08 * 0.4 + math.pi * 0.04**2, rel=0.01)
    assert capsule[:, 0].min() == pytest.approx(-0.04) and capsule[:, 0].max() == pytest.approx(
        0.44
    )


def test_box_faces_can_be_split_into_a_grid() -> None:
    box = CASES[0][1]
    fine = body_mesh(box, box_divisions=4)
    assert len(fine.indices) == 6 * 4 * 4 * 2 and len(body_mesh(box).indices) == 12
    assert volume(fine) == pytest.approx(0.4 * 0.2 * 0.1)
    assert np.allclose(fine.bounds[0], body_mesh(box).bounds[0])


def test_the_terrain_is_cut_to_the_floors_area() -> None:
    """A step ran from its x to a metre past it, past a small creature's 9 cm floor."""
    from legdsl.export.shapes import ground_meshes
    from legdsl.ir.model import Terrain

    def terrain(kind: str, **params: float) -> Terrain:
        return Terrain(kind, tuple(params.items()), Span("x.leg", 1, 1, 1, 2))

    steps = (
        terrain("step", x=-0.003, height=0.0002),
        terrain("box", x0=0.002, x1=0.3, y0=-1.0, y1=1.0, height=0.0003),
        terrain("step", x=0.5, height=0.001),  # past the floor's end: not drawn
    )
    lo, hi = np.array([-0.0436, -0.04]), np.array([0.0453, 0.04])
    meshes = {name: mesh for name, mesh, _ in ground_meshes(steps, lo, hi)}
    assert set(meshes) == {"floor", "terrain0_step", "terrain1_box"}
    for name in ("terrain0_step", "terrain1_box"):
        low, high = meshes[name].bounds
        assert np.all(low[:2] >= lo - 1e-12) and np.all(high[:2] <= hi + 1e-12), name
    assert meshes["terrain0_step"].bounds[0][0] == pytest.approx(-0.003)
    assert meshes["terrain0_step"].bounds[1][0] == pytest.approx(0.0453)
