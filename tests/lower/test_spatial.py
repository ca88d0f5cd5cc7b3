"""Spatial algebra (lower/spatial.py) on random numbers, against plain numpy 6x6 matrices.

With numeric entries every sympy expression folds to a Float, so the results
can be compared with Featherstone's matrices built here from their definitions.
"""

from __future__ import annotations

import numpy as np
import pytest
from sympy import Float

from legdsl.lower import spatial as sp
from legdsl.lower.straightline import Block

RNG = np.random.default_rng(20260101)
TOL = 1e-12


def vec(a: np.ndarray) -> sp.Vec:
    return (Float(a[0]), Float(a[1]), Float(a[2]))


def mat(m: np.ndarray) -> sp.Mat:
    return (vec(m[0]), vec(m[1]), vec(m[2]))


def arr(x: object) -> np.ndarray:
    return np.array(x, dtype=float)


def motion6(m: sp.Motion) -> np.ndarray:
    return np.concatenate([arr(m.w), arr(m.u)])


def force6(f: sp.Force) -> np.ndarray:
    return np.concatenate([arr(f.n), arr(f.f)])


def rotation() -> np.ndarray:
    q, r = np.linalg.qr(RNG.normal(size=(3, 3)))
    q = q @ np.diag(np.sign(np.diag(r)))
    return q if np.linalg.det(q) > 0 else -q


def skew_np(r: np.ndarray) -> np.ndarray:
    return np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])


def plucker(e: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Featherstone's X = [[E, 0], [-E r×, E]] for motion vectors."""
    out = np.zeros((6, 6))
    out[:3, :3] = e
    out[3:, 3:] = e
    out[3:, :3] = -e @ skew_np(r)
    return out


def crm(v: np.ndarray) -> np.ndarray:
    """v×: the motion cross product as a 6x6 matrix."""
    out = np.zeros((6, 6))
    out[:3, :3] = skew_np(v[:3])
    out[3:, 3:] = skew_np(v[:3])
    out[3:, :3] = skew_np(v[3:])
    return out


def random_motion() -> sp.Motion:
    return sp.Motion(vec(RNG.normal(size=3)), vec(RNG.normal(size=3)))


def random_force() -> sp.Force:
    return sp.Force(vec(RNG.normal(size=3)), vec(RNG.normal(size=3)))


def random_transform() -> tuple[sp.Transform, np.ndarray, np.ndarray]:
    e, r = rotation(), RNG.normal(size=3)
    return sp.Transform(mat(e), vec(r)), e, r


def random_body() -> tuple[sp.RigidInertia, np.ndarray]:
    mass, com = RNG.uniform(0.5, 3.0), RNG.normal(size=3) * 0.3
    a = RNG.normal(size=(3, 3))
    inertia = a @ a.T + np.eye(3) * 0.1
    body = sp.RigidInertia.of_body(Float(mass), vec(com), mat(inertia))
    # the 6x6 spatial inertia about the origin (Featherstone eq. 2.63)
    cx = skew_np(com)
    full = np.zeros((6, 6))
    full[:3, :3] = inertia + mass * cx @ cx.T
    full[:3, 3:] = mass * cx
    full[3:, :3] = mass * cx.T
    full[3:, 3:] = mass * np.eye(3)
    return body, full


@pytest.mark.parametrize("trial", range(5))
def test_three_vector_algebra(trial: int) -> None:
    a, b = RNG.normal(size=3), RNG.normal(size=3)
    m, n = RNG.normal(size=(3, 3)), RNG.normal(size=(3, 3))
    np.testing.assert_allclose(arr(sp.cross(vec(a), vec(b))), np.cross(a, b), atol=TOL)
    np.testing.assert_allclose(float(sp.dot(vec(a), vec(b))), a @ b, atol=TOL)
    np.testing.assert_allclose(arr(sp.matvec(sp.skew(vec(a)), vec(b))), np.cross(a, b), atol=TOL)
    np.testing.assert_allclose(arr(sp.matmul(mat(m), mat(n))), m @ n, atol=TOL)
    np.testing.assert_allclose(arr(sp.tmatvec(mat(m), vec(a))), m.T @ a, atol=TOL)
    np.testing.assert_allclose(arr(sp.outer(vec(a), vec(b))), np.outer(a, b), atol=TOL)


@pytest.mark.parametrize("trial", range(5))
def test_rodrigues_is_a_rotation_about_its_axis(trial: int) -> None:
    axis = RNG.normal(size=3)
    axis /= np.linalg.norm(axis)
    angle = RNG.uniform(-np.pi, np.pi)
    r = arr(sp.rodrigues(vec(axis), Float(np.cos(angle)), Float(np.sin(angle))))
    np.testing.assert_allclose(r @ r.T, np.eye(3), atol=TOL)
    assert np.linalg.det(r) == pytest.approx(1.0, abs=TOL)
    np.testing.assert_allclose(r @ axis, axis, atol=TOL)
    v = np.cross(axis, RNG.normal(size=3))  # perpendicular to the axis
    rv = r @ v
    assert v @ rv == pytest.approx(np.cos(angle) * (v @ v), abs=1e-10)
    assert axis @ np.cross(v, rv) == pytest.approx(np.sin(angle) * (v @ v), abs=1e-10)


@pytest.mark.parametrize("trial", range(5))
def test_transform_of_motion_and_force_matches_plucker(trial: int) -> None:
    x, e, r = random_transform()
    m, f = random_motion(), random_force()
    xm = plucker(e, r)
    np.testing.assert_allclose(motion6(x.motion(m)), xm @ motion6(m), atol=TOL)
    np.testing.assert_allclose(force6(x.force_to_parent(f)), xm.T @ force6(f), atol=TOL)


@pytest.mark.parametrize("trial", range(5))
def test_motion_force_duality(trial: int) -> None:
    # power is frame-invariant: (X m) . f_child = m . (X^T f_child)
    x, _, _ = random_transform()
    m, f = random_motion(), random_force()
    child = float(x.motion(m).dot(f))
    parent = float(m.dot(x.force_to_parent(f)))
    assert child == pytest.approx(parent, abs=1e-10)
    # and v x* is minus the dual of v x:  (v x m) . f = -m . (v x* f)
    v = random_motion()
    assert float(v.cross(m).dot(f)) == pytest.approx(-float(m.dot(v.cross_force(f))), abs=1e-10)
    np.testing.assert_allclose(motion6(v.cross(m)), crm(motion6(v)) @ motion6(m), atol=TOL)
    np.testing.assert_allclose(force6(v.cross_force(f)), -crm(motion6(v)).T @ force6(f), atol=TOL)


@pytest.mark.parametrize("trial", range(5))
def test_transforms_compose_and_invert(trial: int) -> None:
    (x1, e1, r1), (x2, e2, r2) = random_transform(), random_transform()
    m = random_motion()
    # parent -> middle -> child equals one transform with E = E2 E1, r = r1 + E1^T r2
    composed = sp.Transform(mat(e2 @ e1), vec(r1 + e1.T @ r2))
    np.testing.assert_allclose(
        motion6(x2.motion(x1.motion(m))), motion6(composed.motion(m)), atol=TOL
    )
    np.testing.assert_allclose(plucker(e2 @ e1, r1 + e1.T @ r2), plucker(e2, r2) @ plucker(e1, r1))
    # the inverse: E^T, and the parent origin seen from the child, -E r
    inverse = sp.Transform(mat(e1.T), vec(-e1 @ r1))
    np.testing.assert_allclose(motion6(inverse.motion(x1.motion(m))), motion6(m), atol=TOL)


@pytest.mark.parametrize("trial", range(5))
def test_rigid_inertia_times_motion_and_moved_to_the_parent(trial: int) -> None:
    body, full = random_body()
    m = random_motion()
    np.testing.assert_allclose(force6(body.times(m)), full @ motion6(m), atol=1e-11)
    x, e, r = random_transform()
    moved = x.rigid_to_parent(body, Block())
    xm = plucker(e, r)
    expected = xm.T @ full @ xm
    np.testing.assert_allclose(force6(moved.times(m)), expected @ motion6(m), atol=1e-10)
    assert float(moved.mass) == pytest.approx(float(body.mass))
    # as an articulated inertia the same matrix
    np.testing.assert_allclose(arr(body.articulated().rows()), full, atol=1e-11)


@pytest.mark.parametrize("trial", range(5))
def test_articulated_inertia_moved_to_the_parent(trial: int) -> None:
    a = RNG.normal(size=(6, 6))
    full = a @ a.T + np.eye(6)
    art = sp.ArticulatedInertia(mat(full[:3, :3]), mat(full[:3, 3:]), mat(full[3:, 3:]))
    np.testing.assert_allclose(arr(art.rows()), full, atol=TOL)
    x, e, r = random_transform()
    moved = x.articulated_to_parent(art, Block())
    xm = plucker(e, r)
    np.testing.assert_allclose(arr(moved.rows()), xm.T @ full @ xm, atol=1e-10)
    left = random_force()
    update = art.minus_outer(left, left)
    np.testing.assert_allclose(
        arr(update.rows()), full - np.outer(force6(left), force6(left)), atol=TOL
    )


def test_solve_spd_matches_numpy() -> None:
    a = RNG.normal(size=(6, 6))
    matrix = a @ a.T + 6 * np.eye(6)
    rhs = RNG.normal(size=6)
    entries = [[Float(v) for v in row] for row in matrix]
    got = sp.solve_spd(Block(), entries, [Float(v) for v in rhs])
    np.testing.assert_allclose(arr(got), np.linalg.solve(matrix, rhs), rtol=1e-12, atol=1e-12)
