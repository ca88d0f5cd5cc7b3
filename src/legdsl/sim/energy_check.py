"""A run whose energy grew without a source, found in what it recorded, and told as a divergence.

Nothing in a creature makes energy but its actuators and its controller: gravity and the
springs of the ground, the joint stops and the actuators store it, their dampers and the
ground's friction take it away. A step too large for a stiff spring (a light leg's tip on a
stiff, damped ground) feeds energy in instead: the total leaps by orders of magnitude in a
step or two, the creature is flung, and the run could end as an ordinary fall, or at its
time, when no velocity was past the divergence rule's limit at a check.

Over a window of the recording (up to ``WINDOW`` samples) the total energy (kinetic,
gravitational, elastic) can rise by no more than the actuators' positive work in it plus
what the springs hold at its end: a controller that moves a spring's rest or a servo's
setpoint, or stiffens it, stores energy in it with no work, and all of that is in the elastic
energy. What the integrator adds at a sound step is a small part of the energy in motion and
in the springs; a rise past that bound by more than ``RISE`` times the energy scale (the most
the creature had in motion and in its springs so far, plus a tenth of its weight times its
height, plus a tenth of the actuators' work in the window) is no motion of the creature's
own. The shipped creatures' and the outside ones' runs, hops, jumps and gallops stay under
the bound (their largest rise past it is under a hundredth of the scale, at 0.4 ms and at
0.8 ms); the blow-up of a light leg on a stiff ground rises past it 5 to 500 times the scale.

``told`` looks at a run that ended ok or fell (a divergence found while it ran is told
already) and tells such a rise as a divergence, with its likely cause at the sample the rise
started from (``legdsl.sim.causes``), or a foot the ground pushed under a step's edge by its end. It reads the recorded samples alone, which both backends
record bit for bit alike, so the run's steps, its recording and the C runtime are as they
were, and both backends tell the same.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from legdsl.sim.causes import cause_at
from legdsl.sim.recorder import TooFast
from legdsl.sim.run_loop import RunResult
from legdsl.sim.sizes import DIVERGENCE_HEIGHT
from legdsl.sim.trajectory import Trajectory

WINDOW = 16  # samples: the longest window looked at
RISE = 2.0  # a rise past the bound by this many times the energy scale is no creature's own
FLOOR = 0.1  # the energy scale's floor: this share of the weight times the height at the start
FLOOR_HEIGHT = 1e-3  # m: the least height of the floor
# the scale's share of the actuators' work in the window: its quadrature at a step (semi-implicit
# Euler's is of first order) is off by a part of it, where a weightless rig starts from rest
SLACK = 0.1


@dataclass(frozen=True)
class EnergyRise:
    """The total energy rose from ``before`` (at sample ``start``, time ``t0``) to ``after``
    (at sample ``end``, ``t1``) with only ``work`` of the actuators' positive work between;
    ``ratio`` is how far past the bound it went, in the energy scale at its start."""

    start: int
    end: int
    t0: float
    t1: float
    before: float
    after: float
    work: float
    ratio: float

    def said(self, scale: float = 1.0) -> str:
        """The rise in words, as the creature scaled by ``scale``'s (a ``--scale L`` run's)."""
        n = self.end - self.start
        energy, tick = scale**4, math.sqrt(scale)
        return (
            f"the total energy rose from {self.before * energy:.4g} J at t = {self.t0 * tick:.4f} "
            f"s to {self.after * energy:.4g} J at t = {self.t1 * tick:.4f} s "
            f"({'one sample' if n == 1 else f'{n} samples'}"
            f" later) with only {self.work * energy:.3g} J of actuator work between, and nothing else in a "
            "creature adds energy"
        )


def energy_floor(traj: Trajectory) -> float:
    """The least energy scale: ``FLOOR`` times the creature's weight times its height at the
    start (its centre of mass over z = 0, or its longest leg; at least ``FLOOR_HEIGHT``)."""
    if not len(traj):
        return 0.0
    heights = [abs(float(traj.com[0, 2])), *traj.leg_length[0].tolist(), FLOOR_HEIGHT]
    return FLOOR * traj.total_mass * traj.gravity * max(h for h in heights if np.isfinite(h))


def rises(traj: Trajectory) -> list[EnergyRise]:
    """For each window length (1 to ``WINDOW`` samples), its largest rise past the bound; none
    for a recording without the actuators' work (an older legdsl's)."""
    n = len(traj)
    if n < 2 or traj.work_positive.shape[0] != n:
        return []
    total = traj.kinetic + traj.potential + traj.elastic
    live = traj.kinetic + traj.elastic
    work = traj.work_positive.sum(axis=1)
    finite = np.isfinite(total) & np.isfinite(live) & np.isfinite(work)
    # the most energy in motion and in the springs up to each sample, and the floor
    scale = np.maximum.accumulate(np.where(finite, live, 0.0)) + energy_floor(traj)
    found = []
    for lag in range(1, min(WINDOW, n - 1) + 1):
        worked = work[lag:] - work[:-lag]
        past = total[lag:] - total[:-lag] - worked - traj.elastic[lag:]
        room = scale[:-lag] + SLACK * worked  # > 0 but for a weightless creature at rest
        ratio = np.divide(past, room, out=np.zeros(n - lag), where=room > 0)
        ratio[~(finite[lag:] & finite[:-lag])] = -np.inf
        a = int(np.argmax(ratio))
        b = a + lag
        found.append(EnergyRise(a, b, float(traj.t[a]), float(traj.t[b]), float(total[a]),
                                float(total[b]), float(work[b] - work[a]), float(ratio[a])))  # fmt: skip
    return found


def unexplained_rise(traj: Trajectory) -> EnergyRise | None:
    """The rise past the bound by more than ``RISE`` times the energy scale in the shortest
    window that has one (the largest there), or None."""
    return next((r for r in rises(traj) if r.ratio > RISE), None)


def told(sim: Any, result: RunResult) -> RunResult:
    """``result`` of ``sim`` (a ``legdsl.sim.simulate.Simulation``, at the run's end), a run
    that ended ok or fell, told as a divergence if its energy rose without a source: the
    rise, its likely cause and how the run went on. Else, and for a run diverged or
    interrupted already, as it is."""
    if result.status not in ("ok", "fell"):
        return result
    try:
        rise = unexplained_rise(result.trajectory)
    except MemoryError:  # its recording took the memory there was: the run is as it ended
        return result
    if rise is None:
        return result
    traj = result.trajectory
    start = traj.q[rise.start].tolist()
    # the cause at the rise's start, and a foot pushed under a step's edge through its end
    likely = cause_at(sim, start, None, traj.head(rise.start + 1), traj.head(rise.end + 1))
    cause = f"{rise.said(sim.size_scale)}. Likely cause: {likely}"
    then = f"fell at t = {result.sim_time:.4f} s: {result.message}"
    if result.status == "ok":
        then = f"ran on to its end at t = {result.sim_time:.4f} s"
    message = f"the simulation diverged at t = {rise.t1:.4f} s: {cause}. After it the run {then}"
    return dataclasses.replace(
        result, status="diverged", message=message, cause=cause, diverged_at=rise.t1
    )


# A velocity past the divergence limit by less than OWN_PAST times it, that was at OWN_SHARE of
# it or more at the last sample recorded, with no energy rise without a source up to there, is
# the creature's own motion: a step blowing up (or a rate near gimbal lock) leaps far past it
# from an ordinary speed within a few steps.
OWN_SHARE, OWN_PAST = 0.5, 1.5


def own_speed(sim: Any, err: BaseException | None, run: Trajectory | None) -> str | None:
    """A speed past the divergence rule's fixed limit that nothing grew to (``err``, at the
    state now, of ``sim`` that recorded ``run``), told where no other cause is found: the
    creature's own, as a giant reaches in its first fall (the hopper scaled by 1e6 fell to
    1000 m/s in 102 s, and was told to try a smaller step or rk4, which changed nothing).
    None for any other divergence."""
    if not isinstance(err, TooFast) or run is None or len(run) < 2:
        return None
    if not err.speed < OWN_PAST * err.limit:
        return None
    last = np.flatnonzero(np.all(np.isfinite(run.v), axis=1))
    if not len(last) or not abs(run.v[last[-1], err.index]) >= OWN_SHARE * err.limit:
        return None
    if unexplained_rise(run.head(int(last[-1]) + 1)) is not None:
        return None
    model, k, tick = sim.model, err.index, math.sqrt(sim.size_scale)
    unit = "rad/s" if model.v_angular[k] else "m/s"
    speed_then = abs(run.v[last[-1], k]) * sim.v_factors[k]
    fall = run.com_vel[last[-1], 2] * sim.size_scale**0.5
    how = (f"falling ({-fall:.3g} m/s down at its centre of mass)"
           if fall < -OWN_SHARE * err.limit * sim.v_factors[k] and unit == "m/s"
           else "in its own motion")  # fmt: skip
    return (
        f"nothing grew without bound: the creature reached this speed {how}, its energy up to "
        f"the last sample (t = {run.t[last[-1]] * tick:.4f} s, {model.v_names[k]} at "
        f"{speed_then:.3g} {unit}) no more than it started with and its actuators' work gave "
        f"it; a step or an integrator changes nothing here: the limit is fixed for every "
        f"creature standing {DIVERGENCE_HEIGHT * 100:g} cm or more, and one this large reaches "
        f"it (docs/scaling.md#far-from-a-metre-what-follows-the-creatures-size). What was "
        f"recorded up to here stands; a --time under {sim.t * tick:.4g} s ends the run before it"
    )
