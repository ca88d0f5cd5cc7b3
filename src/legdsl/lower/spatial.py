"""Spatial vector algebra (Featherstone, *Rigid Body Dynamics Algorithms*, ch. 2) on sympy.

Everything is kept as 3-vectors and 3x3 blocks of sympy expressions, so
that the zero and unit entries of axes, offsets and inertias fold away as
the algorithms multiply them out. Conventions:

* A motion vector is ``(w, u)``: angular velocity, and the linear velocity
  of the body point at the frame's origin, both in the frame's axes. A force
  vector is ``(n, f)``: moment about the origin, and force.
* A ``Transform`` takes motion vectors from a parent frame to a child frame:
  ``E`` turns parent coordinates into child coordinates (it is the transpose
  of the child's orientation in the parent) and ``r`` is the child origin in
  parent coordinates, so X = [[E, 0], [-E r×, E]].
* A rigid inertia at a frame origin is ``(mass, h, inertia)`` with ``h =
  mass * com`` and ``inertia`` about the origin; an articulated inertia is a
  general symmetric 6x6 matrix [[A, B], [Bᵀ, C]].

``let`` methods hand every entry to a ``Block`` so each step's results
become temporaries, keeping expressions small.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from sympy import Expr, Integer

from legdsl.lower.straightline import Block

Vec = tuple[Expr, Expr, Expr]
Mat = tuple[Vec, Vec, Vec]

_0, _1 = Integer(0), Integer(1)
ZERO: Vec = (_0, _0, _0)
ZERO_MAT: Mat = (ZERO, ZERO, ZERO)
EYE: Mat = ((_1, _0, _0), (_0, _1, _0), (_0, _0, _1))


# ------------------------------------------------------------------ 3-vectors and 3x3 blocks
def add(a: Vec, b: Vec) -> Vec:
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a: Vec, b: Vec) -> Vec:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def scale(k: Expr, a: Vec) -> Vec:
    return (k * a[0], k * a[1], k * a[2])


def dot(a: Vec, b: Vec) -> Expr:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a: Vec, b: Vec) -> Vec:
    return (
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    )


def matvec(m: Mat, a: Vec) -> Vec:
    return (dot(m[0], a), dot(m[1], a), dot(m[2], a))


def column(m: Mat, j: int) -> Vec:
    return (m[0][j], m[1][j], m[2][j])


def transpose(m: Mat) -> Mat:
    return (column(m, 0), column(m, 1), column(m, 2))


def tmatvec(m: Mat, a: Vec) -> Vec:
    """mᵀ a."""
    return matvec(transpose(m), a)


def matmul(a: Mat, b: Mat) -> Mat:
    bt = transpose(b)
    return (
        (dot(a[0], bt[0]), dot(a[0], bt[1]), dot(a[0], bt[2])),
        (dot(a[1], bt[0]), dot(a[1], bt[1]), dot(a[1], bt[2])),
        (dot(a[2], bt[0]), dot(a[2], bt[1]), dot(a[2], bt[2])),
    )


def madd(a: Mat, b: Mat) -> Mat:
    return (add(a[0], b[0]), add(a[1], b[1]), add(a[2], b[2]))


def msub(a: Mat, b: Mat) -> Mat:
    return (sub(a[0], b[0]), sub(a[1], b[1]), sub(a[2], b[2]))


def outer(a: Vec, b: Vec) -> Mat:
    return (scale(a[0], b), scale(a[1], b), scale(a[2], b))


def skew(r: Vec) -> Mat:
    """r× as a matrix: skew(r) a = r × a."""
    return ((_0, -r[2], r[1]), (r[2], _0, -r[0]), (-r[1], r[0], _0))


def symmetric(m: Mat) -> Mat:
    """The upper triangle mirrored: for matrices known to be symmetric, so each entry is made once."""
    return ((m[0][0], m[0][1], m[0][2]), (m[0][1], m[1][1], m[1][2]), (m[0][2], m[1][2], m[2][2]))


def let_vec(block: Block, a: Vec) -> Vec:
    return (block.let(a[0]), block.let(a[1]), block.let(a[2]))


def let_mat(block: Block, m: Mat) -> Mat:
    return (let_vec(block, m[0]), let_vec(block, m[1]), let_vec(block, m[2]))


def let_sym(block: Block, m: Mat) -> Mat:
    return let_mat(block, symmetric(m))


def rotate_sym(e: Mat, m: Mat, block: Block) -> Mat:
    """eᵀ m e for a symmetric m, in two steps so each product stays small."""
    return let_sym(block, matmul(let_mat(block, matmul(transpose(e), m)), e))


def rotate(e: Mat, m: Mat, block: Block) -> Mat:
    """eᵀ m e."""
    return let_mat(block, matmul(let_mat(block, matmul(transpose(e), m)), e))


def rodrigues(axis: Vec, c: Expr, s: Expr) -> Mat:
    """The rotation by an angle with cosine c and sine s about a unit axis: c 1 + s a× + (1 - c) a aᵀ."""
    k = skew(axis)

    def entry(i: int, j: int) -> Expr:
        return (c if i == j else _0) + s * k[i][j] + (1 - c) * axis[i] * axis[j]

    return (
        (entry(0, 0), entry(0, 1), entry(0, 2)),
        (entry(1, 0), entry(1, 1), entry(1, 2)),
        (entry(2, 0), entry(2, 1), entry(2, 2)),
    )


# ------------------------------------------------------------------ spatial vectors
@dataclass(frozen=True)
class Motion:
    w: Vec
    u: Vec

    def __add__(self, other: Motion) -> Motion:
        return Motion(add(self.w, other.w), add(self.u, other.u))

    def scaled(self, k: Expr) -> Motion:
        return Motion(scale(k, self.w), scale(k, self.u))

    def dot(self, f: Force) -> Expr:
        return dot(self.w, f.n) + dot(self.u, f.f)

    def cross(self, m: Motion) -> Motion:
        """self ×m m: how a motion vector changes as the frame moves with velocity ``self``."""
        return Motion(cross(self.w, m.w), add(cross(self.w, m.u), cross(self.u, m.w)))

    def cross_force(self, f: Force) -> Force:
        """self ×* f."""
        return Force(add(cross(self.w, f.n), cross(self.u, f.f)), cross(self.w, f.f))

    def let(self, block: Block) -> Motion:
        return Motion(let_vec(block, self.w), let_vec(block, self.u))


ZERO_MOTION = Motion(ZERO, ZERO)


@dataclass(frozen=True)
class Force:
    n: Vec
    f: Vec

    def __add__(self, other: Force) -> Force:
        return Force(add(self.n, other.n), add(self.f, other.f))

    def scaled(self, k: Expr) -> Force:
        return Force(scale(k, self.n), scale(k, self.f))

    def let(self, block: Block) -> Force:
        return Force(let_vec(block, self.n), let_vec(block, self.f))


ZERO_FORCE = Force(ZERO, ZERO)


@dataclass(frozen=True)
class RigidInertia:
    mass: Expr
    h: Vec  # mass * centre of mass
    inertia: Mat  # about the frame origin

    @classmethod
    def of_body(cls, mass: Expr, com: Vec, inertia_at_com: Mat) -> RigidInertia:
        cc = dot(com, com)
        shift = msub(((cc, _0, _0), (_0, cc, _0), (_0, _0, cc)), outer(com, com))
        return cls(mass, scale(mass, com), madd(inertia_at_com, _scale_mat(mass, shift)))

    def __add__(self, other: RigidInertia) -> RigidInertia:
        return RigidInertia(
            self.mass + other.mass, add(self.h, other.h), madd(self.inertia, other.inertia)
        )

    def times(self, m: Motion) -> Force:
        return Force(
            add(matvec(self.inertia, m.w), cross(self.h, m.u)),
            sub(scale(self.mass, m.u), cross(self.h, m.w)),
        )

    def articulated(self) -> ArticulatedInertia:
        m = self.mass
        return ArticulatedInertia(
            self.inertia, skew(self.h), ((m, _0, _0), (_0, m, _0), (_0, _0, m))
        )

    def let(self, block: Block) -> RigidInertia:
        return RigidInertia(
            block.let(self.mass), let_vec(block, self.h), let_sym(block, self.inertia)
        )


ZERO_RIGID = RigidInertia(_0, ZERO, ZERO_MAT)


@dataclass(frozen=True)
class ArticulatedInertia:
    a: Mat  # angular-angular, symmetric
    b: Mat  # angular-linear
    c: Mat  # linear-linear, symmetric

    def __add__(self, other: ArticulatedInertia) -> ArticulatedInertia:
        return ArticulatedInertia(
            madd(self.a, other.a), madd(self.b, other.b), madd(self.c, other.c)
        )

    def times(self, m: Motion) -> Force:
        return Force(
            add(matvec(self.a, m.w), matvec(self.b, m.u)),
            add(tmatvec(self.b, m.w), matvec(self.c, m.u)),
        )

    def minus_outer(self, left: Force, right: Force) -> ArticulatedInertia:
        """self - left rightᵀ, for a symmetric result (the articulated-body update)."""
        return ArticulatedInertia(
            symmetric(msub(self.a, outer(left.n, right.n))),
            msub(self.b, outer(left.n, right.f)),
            symmetric(msub(self.c, outer(left.f, right.f))),
        )

    def rows(self) -> list[list[Expr]]:
        """The full 6x6 matrix."""
        bt = transpose(self.b)
        return [[*self.a[i], *self.b[i]] for i in range(3)] + [
            [*bt[i], *self.c[i]] for i in range(3)
        ]

    def let(self, block: Block) -> ArticulatedInertia:
        return ArticulatedInertia(
            let_sym(block, self.a), let_mat(block, self.b), let_sym(block, self.c)
        )


ZERO_ARTICULATED = ArticulatedInertia(ZERO_MAT, ZERO_MAT, ZERO_MAT)


def _scale_mat(k: Expr, m: Mat) -> Mat:
    return (scale(k, m[0]), scale(k, m[1]), scale(k, m[2]))


# ------------------------------------------------------------------ frame changes
@dataclass(frozen=True)
class Transform:
    e: Mat  # parent coordinates -> child coordinates
    r: Vec  # child origin in parent coordinates

    def motion(self, m: Motion) -> Motion:
        """A parent-frame motion vector in child coordinates."""
        return Motion(matvec(self.e, m.w), matvec(self.e, sub(m.u, cross(self.r, m.w))))

    def force_to_parent(self, f: Force) -> Force:
        """A child-frame force vector in parent coordinates (Xᵀ f)."""
        fp = tmatvec(self.e, f.f)
        return Force(add(tmatvec(self.e, f.n), cross(self.r, fp)), fp)

    def rigid_to_parent(self, body: RigidInertia, block: Block) -> RigidInertia:
        """Xᵀ I X for a rigid inertia: rotate, then move the reference point."""
        h = let_vec(block, tmatvec(self.e, body.h))
        inertia = rotate_sym(self.e, body.inertia, block)
        if self.r == ZERO:
            return RigidInertia(body.mass, h, inertia)
        h2 = let_vec(block, add(h, scale(body.mass, self.r)))
        # I' = I - (r×)(h×) - (h'×)(r×) = I + (r·h + r·h') 1 - h rᵀ - r h'ᵀ
        d = dot(self.r, h) + dot(self.r, h2)
        moved = msub(
            madd(inertia, ((d, _0, _0), (_0, d, _0), (_0, _0, d))),
            madd(outer(h, self.r), outer(self.r, h2)),
        )
        return RigidInertia(body.mass, h2, let_sym(block, moved))

    def articulated_to_parent(self, body: ArticulatedInertia, block: Block) -> ArticulatedInertia:
        """Xᵀ I X for an articulated inertia: rotate, then move the reference point."""
        a = rotate_sym(self.e, body.a, block)
        b = rotate(self.e, body.b, block)
        c = rotate_sym(self.e, body.c, block)
        if self.r == ZERO:
            return ArticulatedInertia(a, b, c)
        rx = skew(self.r)
        b2 = let_mat(block, madd(b, matmul(rx, c)))
        # A' = A + r× Bᵀ - B' r×, with B' = B + r× C
        a2 = let_sym(block, msub(madd(a, matmul(rx, transpose(b))), matmul(b2, rx)))
        return ArticulatedInertia(a2, b2, c)


def solve_spd(block: Block, matrix: Sequence[Sequence[Expr]], rhs: Sequence[Expr]) -> list[Expr]:
    """x with matrix x = rhs, for a symmetric positive definite matrix, as straight-line code.

    An unrolled LDLᵀ factorisation on the entries' run-time values: the entries
    are temporaries, so no symbolic inverse is ever formed.
    """
    n = len(rhs)
    low: list[list[Expr]] = [[_0] * n for _ in range(n)]  # L, unit lower triangular
    scaled: list[list[Expr]] = [[_0] * n for _ in range(n)]  # L D, with D on the diagonal
    d_inv: list[Expr] = [_0] * n
    for j in range(n):
        for i in range(j, n):
            partial = sum((scaled[i][k] * low[j][k] for k in range(j)), _0)
            scaled[i][j] = block.let(matrix[i][j] - partial)
        d_inv[j] = block.let(1 / scaled[j][j])
        for i in range(j + 1, n):
            low[i][j] = block.let(scaled[i][j] * d_inv[j])
    y: list[Expr] = []
    for i in range(n):
        y.append(block.let(rhs[i] - sum((low[i][k] * y[k] for k in range(i)), _0)))
    x: list[Expr] = [_0] * n
    for i in reversed(range(n)):
        x[i] = block.let(y[i] * d_inv[i] - sum((low[k][i] * x[k] for k in range(i + 1, n)), _0))
    return x
