"""Springs and servos on coupled coordinates, checked together against the step.

``legdsl.sim.stability`` checks each spring or servo alone, on its coordinate's effective mass
(the inverse of the diagonal of M(q)^-1: every other coordinate free). Two on coordinates
that share a light mode each pass so, and together diverge within steps: a ball joint whose
first and last axes are 20 deg apart (its middle angle 70 deg from a right angle) turns a tail
about its light axis with both, and the mode's inertia is far under either coordinate's.
Here they are checked together, on the block W of M^-1 over the coordinates they act on
(every other coordinate free): the linear system x'' = -W (K x + B x'), with K and B their
stiffnesses and dampings summed on each coordinate, stepped as the run steps it, is stable
while the spectral radius of its step matrix is at most 1 (semi-implicit Euler: v+ = v - h W
(K x + B v), x+ = x + h v+; RK4: its polynomial of degree 4 in h A). On one coordinate this is
the Jury bound the single check uses; on several it holds for each mode of the block.

A ball joint near gimbal lock is said to be the reason where the same check passes with the
joint's middle angle at 0 (``InverseInertia.unlocked``): the pose, not the gains, is at fault.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from legdsl.ir.model import Model, axes_spread

SLACK = 1e-6  # a spectral radius past 1 by this is growth (an undamped mode's is 1 to rounding)
SHARE = 0.1  # a coordinate takes part in the growing mode past this share of its largest part
BISECTIONS = 48
# a ball joint whose axes lie within this of one plane is looked at as a reason (deg)
LOCK_LOOKED_AT = 45.0


class InverseInertia(list[float]):
    """The diagonal of M(q)^-1 at a pose (the list the single checks read), with the whole
    of it (``matrix``) and, for the coordinates of each ball joint near gimbal lock there,
    M^-1 with its middle angle at 0 and what is said of the pose (``unlocked``, by velocity
    coordinate)."""

    def __init__(self, matrix: np.ndarray,
                 unlocked: dict[int, tuple[np.ndarray, str]] | None = None) -> None:  # fmt: skip
        super().__init__(float(x) for x in np.diag(matrix))
        self.matrix = matrix
        self.unlocked = unlocked or {}


def inverse_inertia(
    model: Model, mass_matrix: Callable[[list[float]], Any], q: Sequence[float]
) -> InverseInertia:
    """M(q)^-1 (zeros if M is singular there) and its ball joints near gimbal lock, from
    ``mass_matrix`` (the dynamics' ``mass_matrix``)."""
    pose = list(q)
    matrix = _inverse(mass_matrix(pose))
    unlocked: dict[int, tuple[np.ndarray, str]] = {}
    for joint in model.joints:
        if joint.kind != "ball":
            continue
        angles = [pose[d.q_index] for d in joint.dofs]
        spread = axes_spread([d.axis for d in joint.dofs], angles)
        near = math.degrees(math.asin(min(spread, 1.0)))
        if not near < LOCK_LOOKED_AT:
            continue
        middle = joint.dofs[1]
        turned = list(pose)
        turned[middle.q_index] = 0.0
        said = (
            f"ball joint '{joint.name}' is {near:.2g} deg from gimbal lock here ({middle.name} "
            f"= {math.degrees(angles[1]):.3g} deg: its axes lie within {near:.2g} deg of one "
            f"plane), and its coordinates' inertia shrinks the nearer it comes; start it "
            f"further from there, or give it axes that keep it away"
        )
        away = _inverse(mass_matrix(turned))
        for d in joint.dofs:
            unlocked[d.v_index] = (away, said)
    return InverseInertia(matrix, unlocked)


def _inverse(mass: Any) -> np.ndarray:
    m = np.asarray(mass, dtype=float)
    try:
        return np.linalg.inv(m)
    except np.linalg.LinAlgError:
        return np.zeros_like(m)


@dataclass(frozen=True)
class Pull:
    """A spring or servo's part in the coupled check: its stiffness and damping on velocity
    coordinate ``v_index`` (0 for a setting the controller writes)."""

    v_index: int
    gain: float
    damping: float


@dataclass(frozen=True)
class Coupled:
    """Springs and servos (``members``: indices into the pulls) whose coupled coordinates
    make a mode the step cannot follow: their ``setting`` ('stiffness' or 'damping') times
    ``factor`` at most is stable (None if no factor is), as is a step under ``dt_limit``;
    ``why`` names a ball joint near gimbal lock where that is the reason."""

    members: tuple[int, ...]
    setting: str
    factor: float | None
    dt_limit: float
    why: str = ""


def _step(w: np.ndarray, k: np.ndarray, b: np.ndarray, h: float, integrator: str) -> np.ndarray:
    """The matrix of one step of x'' = -W (K x + B x') (state x, then v)."""
    n, eye = len(k), np.eye(len(k))
    wk, wb = w * k[None, :], w * b[None, :]  # W diag(k), W diag(b)
    if integrator == "rk4":
        a = h * np.block([[np.zeros((n, n)), eye], [-wk, -wb]])
        a2 = a @ a
        return np.eye(2 * n) + a + a2 / 2 + a2 @ a / 6 + a2 @ a2 / 24
    return np.block([[eye - h * h * wk, h * (eye - h * wb)], [-h * wk, eye - h * wb]])


def _radius(w: np.ndarray, k: np.ndarray, b: np.ndarray, h: float, integrator: str) -> float:
    """The spectral radius of ``_step``: past 1, a mode grows at every step."""
    return float(np.max(np.abs(np.linalg.eigvals(_step(w, k, b, h, integrator)))))


def _stable(w: np.ndarray, k: np.ndarray, b: np.ndarray, h: float, integrator: str) -> bool:
    return _radius(w, k, b, h, integrator) <= 1.0 + SLACK


def coupled_too_stiff(
    pulls: Sequence[Pull], inverse: InverseInertia, dt: float, integrator: str
) -> Coupled | None:
    """The springs and servos of ``pulls`` that together diverge at step ``dt`` on the
    inverse inertia ``inverse``, or None if they do not."""
    coords = sorted({p.v_index for p in pulls if p.gain > 0 or p.damping > 0})
    if not coords:
        return None
    at = {v: i for i, v in enumerate(coords)}

    def settings(scaled: set[int], by: float, which: str) -> tuple[np.ndarray, np.ndarray]:
        k, b = np.zeros(len(coords)), np.zeros(len(coords))
        for i, p in enumerate(pulls):
            if p.v_index in at:
                f = by if i in scaled else 1.0
                k[at[p.v_index]] += p.gain * (f if which == "stiffness" else 1.0)
                b[at[p.v_index]] += p.damping * (f if which == "damping" else 1.0)
        return k, b

    def block(matrix: np.ndarray) -> np.ndarray:
        return matrix[np.ix_(coords, coords)]

    w = block(inverse.matrix)
    k, b = settings(set(), 1.0, "stiffness")
    if not np.all(np.isfinite(w)) or _stable(w, k, b, dt, integrator):
        return None
    zero = np.zeros(len(coords))
    setting = "damping" if not _stable(w, zero, b, dt, integrator) else "stiffness"
    members = _taking_part(w, k, b, dt, integrator, pulls, coords, setting)
    factor: float | None = None
    if _stable(w, *settings(set(members), 0.0, setting), dt, integrator):
        factor = _largest(lambda f: _stable(w, *settings(set(members), f, setting), dt,
                                             integrator), 1.0)  # fmt: skip
    dt_limit = _largest(lambda h: _stable(w, k, b, h, integrator), dt)
    whys = dict(inverse.unlocked[pulls[i].v_index][::-1] for i in members
                if pulls[i].v_index in inverse.unlocked)  # fmt: skip
    why = ""
    for said, matrix in whys.items():  # the pose is the reason: out of the lock, it is stable
        if _stable(block(matrix), k, b, dt, integrator):
            why = said
    return Coupled(tuple(members), setting, factor, dt_limit, why)


def _taking_part(w: np.ndarray, k: np.ndarray, b: np.ndarray, dt: float, integrator: str,
                 pulls: Sequence[Pull], coords: list[int], setting: str) -> list[int]:  # fmt: skip
    """The pulls on the coordinates the fastest-growing mode moves (past ``SHARE`` of its
    largest part), with some of ``setting`` to lower."""
    n = len(coords)
    values, vectors = np.linalg.eig(_step(w, k, b, dt, integrator))
    mode = vectors[:, int(np.argmax(np.abs(values)))]
    part = np.abs(mode[:n]) + np.abs(mode[n:]) * dt  # a coordinate's swing and its rate's
    moved = {coords[i] for i in np.flatnonzero(part > SHARE * part.max())}
    own = (lambda p: p.damping) if setting == "damping" else (lambda p: p.gain)
    return [i for i, p in enumerate(pulls) if p.v_index in moved and own(p) > 0]


def _largest(stable: Callable[[float], bool], most: float) -> float:
    """The largest x in (0, most) for which ``stable(x)`` holds (it holds near 0)."""
    low, high = 0.0, most
    for _ in range(BISECTIONS):
        middle = 0.5 * (low + high)
        low, high = (middle, high) if stable(middle) else (low, middle)
    return low
