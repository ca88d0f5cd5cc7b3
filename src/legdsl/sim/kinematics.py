"""The kinematic solve behind ``place LEG at (x = .., z = ..) using SERVO, ..``.

Find the values of the servos' coordinates that put the leg's foot at the
given offset from its hip (in the heading frame: world axes turned by the
root's yaw), and make them the servos' setpoints. The hip point is the origin
of the leg's first joint, fixed in the parent body, so it does not move when
the leg's own coordinates do: the Jacobian of (foot - hip) with respect to
them is exactly the matching columns of the generated contact Jacobian.

Each call takes a few Newton steps on that Jacobian, starting from the
previous solution (or the current pose), so over successive control ticks of
a flight phase it converges to the exact placement. Closed forms are not
attempted: with massive links the solve is transcendental in general, and the
warm-started Newton steps converge in one or two ticks.

Each step's linear solve (two or three unknowns) is ``solve_small``: Gaussian
elimination with partial pivoting in plain floats, whose every operation C
repeats in the same order (runtime/machine.c), so the runs are the same doubles on
both backends and on every processor (LAPACK's result would depend on the kernels
OpenBLAS picks for the processor, and a call into it costs more than the solve).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from legdsl.ir.model import Hip, Model

MAX_STEP = 0.3  # rad or m per Newton step: keeps a far-off first guess from overshooting


@dataclass(frozen=True)
class _Leg:
    foot: int  # contact index
    hip: Hip


class FootPlacer:
    def __init__(self, model: Model, iterations: int = 2):
        self.model = model
        self.iterations = iterations
        self.legs = {
            leg.name: _Leg(
                foot=[c.name for c in model.contacts].index(leg.foot),
                hip=model.leg_hip(leg),
            )
            for leg in model.legs
        }
        self.dofs = {d.name: d for d in model.dofs}
        self.actuator_dof = {a.name: self.dofs[a.dof] for a in model.actuators}
        self.limits = {a.name: self.dofs[a.dof].limits for a in model.actuators}

    def solve(
        self, sim: Any, leg: str, axes: tuple[str, ...], goals: list[float], servos: tuple[str, ...]
    ) -> list[float]:
        """Setpoints for ``servos`` that put the foot at ``goals`` (along ``axes``) from the hip."""
        dyn = sim.dyn
        spec = self.legs[leg]
        dofs = [self.actuator_dof[s] for s in servos]
        rows = ["xyz".index(a) for a in axes]
        q = list(sim.q)
        guess = [sim.actuators.by_name[s].target for s in servos]
        for k, d in enumerate(dofs):
            if not math.isfinite(guess[k]):
                guess[k] = q[d.q_index]
            q[d.q_index] = guess[k]
        yaw = 0.0
        if not self.model.planar:
            rot = dyn.body_poses(q)[0][1]
            yaw = math.atan2(rot[3], rot[0])
        c, s = math.cos(yaw), math.sin(yaw)
        cols = [dof.v_index for dof in dofs]
        for _ in range(self.iterations):
            foot = dyn.contact_positions(q)[spec.foot]
            hip = spec.hip.point(dyn.body_poses(q))
            delta = (foot[0] - hip[0], foot[1] - hip[1], foot[2] - hip[2])
            rel = (c * delta[0] + s * delta[1], -s * delta[0] + c * delta[1], delta[2])
            residual = [rel[r] - g for r, g in zip(rows, goals, strict=True)]
            jac = dyn.contact_jacobians(q)[spec.foot]
            world = [[jac[r][i] for i in cols] for r in range(3)]
            heading = [
                [c * x + s * y for x, y in zip(world[0], world[1], strict=True)],
                [-s * x + c * y for x, y in zip(world[0], world[1], strict=True)],
                world[2],
            ]
            step = solve_small([heading[r] for r in rows], [-x for x in residual])
            if step is None:
                break  # a singular pose (a straight leg): keep the last good guess
            for k, dof in enumerate(dofs):
                guess[k] += clip_step(step[k])
                q[dof.q_index] = guess[k]
        for k, servo in enumerate(servos):
            limits = self.limits[servo]
            if limits is not None:
                guess[k] = min(max(guess[k], limits[0]), limits[1])
        return guess


def clip_step(x: float) -> float:
    """``x`` within ``MAX_STEP`` either way (a NaN passes: the state machine then faults)."""
    if x < -MAX_STEP:
        return -MAX_STEP
    if x > MAX_STEP:
        return MAX_STEP
    return x


def solve_small(a: list[list[float]], b: list[float]) -> list[float] | None:
    """x with a x = b, by Gaussian elimination with partial pivoting (the first row of the
    largest magnitude; each multiplier a division by the pivot) and back substitution, in
    this order of operations, which runtime/machine.c's ``solve_small`` repeats; None where a
    pivot is zero (the matrix is singular)."""
    n = len(b)
    m, x = [list(row) for row in a], list(b)
    for col in range(n):
        p = col
        for r in range(col + 1, n):
            if abs(m[r][col]) > abs(m[p][col]):
                p = r
        if m[p][col] == 0.0:
            return None
        m[col], m[p] = m[p], m[col]
        x[col], x[p] = x[p], x[col]
        for r in range(col + 1, n):
            f = m[r][col] / m[col][col]
            for k in range(col + 1, n):
                m[r][k] = m[r][k] - f * m[col][k]
            x[r] = x[r] - f * x[col]
    for col in reversed(range(n)):
        total = x[col]
        for k in range(col + 1, n):
            total = total - m[col][k] * x[k]
        x[col] = total / m[col][col]
    return x
