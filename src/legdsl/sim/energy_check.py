"""A run whose energy grew without a source, found in what it recorded, and told as a divergence.

Nothing in a creature makes energy but its actuators and its controller: gravity and the
springs of the ground, the joint stops and the actuators store it, their dampers and the
ground's friction take it away. A step too large for a stiff spring (a light leg's tip on a
stiff, damped ground) feeds energy in instead: the total leaps by orders of magnitude in a
step or two, the creature is flung, and the run could end as an ordinary fall, or at its
time, when no velocity was past the divergence rule's limit at a check.

Over a window of the recording (up to ``WINDOW`` samples) the total energy (kinetic,
gravitational, elastic: a spring or servo with a ``max`` holds the potential of its force as
it is clipped, ``legdsl.sim.actuators.stored``) can rise by no more than the actuators'
positive work in it plus what the springs hold at its end: a controller that moves a
spring's rest or a servo's setpoint, or stiffens it, stores energy in it with no work, and all
of that is in the elastic energy. A spring or servo whose stiffness and rest nothing changes in the run, and that has no
``max``, is a source of neither (``held_springs``): its work only gives back what it stored,
which is in the total already, and what it holds is part of the total it started with (a
passive pogo's 5 g foot chattering on the ground at twice its stable step had its leg spring
do 1129 J of positive work, 25 times the drop's energy, and was told ok). What the integrator adds at a sound step is a small part of the energy in motion and
in the springs; a rise past that bound by more than ``RISE`` times the energy scale (the most
the creature had in motion and in its springs so far, plus a tenth of its weight times its
height, plus a tenth of the actuators' work in the window) is no motion of the creature's
own. The shipped creatures' and the outside ones' runs, hops, jumps and gallops stay under
the bound (their largest rise past it is under a hundredth of the scale at their own steps,
and a tenth at 0.8 ms, where the kangaroo's held tail springs are no source); the blow-up of
a light leg on a stiff ground rises past it 5 to 500 times the scale.

``told`` looks at a run that ended ok or fell (a divergence found while it ran is told
already) and tells such a rise as a divergence, with its likely cause at the sample the rise
started from (``legdsl.sim.causes``), or a foot the ground pushed under a step's edge by its end. It reads the recorded samples alone, which both backends
record bit for bit alike, so the run's steps, its recording and the C runtime are as they
were, and both backends tell the same.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from legdsl.sim.causes import cause_at
from legdsl.sim.machine import settings_written
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
class HeldSpring:
    """A spring or servo (actuator ``index``, on coordinate ``q_index``) whose stiffness
    ``gain`` and rest ``target`` stay as they are through the run, and that has no ``max``:
    with its damping it stores what it is given and gives back no more."""

    index: int
    q_index: int
    gain: float
    target: float

    def holds(self, q: np.ndarray) -> np.ndarray:
        """(N,) J: the energy it holds at each pose of ``q`` (N, NQ)."""
        stretch = q[:, self.q_index] - self.target
        return 0.5 * self.gain * stretch * stretch


def held_springs(
    sim: Any, settings: Iterable[tuple[float, float]] | None = None
) -> tuple[HeldSpring, ...]:
    """The springs and servos of ``sim`` (a ``legdsl.sim.simulate.Simulation``) that no
    controller of its run writes the stiffness or the rest of, and that have no ``max`` (one
    with a ``max`` stays a source, its work and what it holds counted: the looser bound): at
    each one's (gain, target) in ``settings`` (a batch copy's), or its settings now."""
    controller = sim.controller
    modules = getattr(controller, "modules", None) or (
        {"": controller.module} if controller is not None else {}
    )
    written = {name for module in modules.values() for name in settings_written(module)}
    states = sim.actuators.states
    values = settings if settings is not None else ((a.gain, a.target) for a in states)
    held = []
    for i, (a, (gain, target)) in enumerate(zip(states, values, strict=False)):  # C pads
        stiff, rest = ("k", "rest") if a.kind == "spring" else ("kp", "setpoint")
        if a.kind == "force" or a.limit is not None:
            continue
        if f"{a.name}.{stiff}" not in written and f"{a.name}.{rest}" not in written:
            held.append(HeldSpring(i, a.q_index, float(gain), float(target)))
    return tuple(held)


def held_in_copies(sim: Any, blocks: dict[str, np.ndarray]) -> list[tuple[HeldSpring, ...]]:
    """Each copy's ``held_springs`` of a batch of ``sim``'s runs, from its actuators' gains and
    targets at its end (``blocks``: the C struct's arrays, a row a copy; a setting no
    controller writes is the copy's own throughout)."""
    rows = zip(blocks["act_gain"], blocks["act_target"], strict=True)
    return [held_springs(sim, zip(gains, targets, strict=True)) for gains, targets in rows]


@dataclass(frozen=True)
class EnergyRise:
    """The total energy rose from ``before`` (at sample ``start``, time ``t0``) to ``after``
    (at sample ``end``, ``t1``) with only ``work`` of the actuators' positive work between
    (and ``given_back``, the held springs', which is no source); ``ratio`` is how far past the
    bound it went, in the energy scale at its start."""

    start: int
    end: int
    t0: float
    t1: float
    before: float
    after: float
    work: float
    ratio: float
    given_back: float = 0.0

    def said(self, scale: float = 1.0) -> str:
        """The rise in words, as the creature scaled by ``scale``'s (a ``--scale L`` run's)."""
        n = self.end - self.start
        energy, tick = scale**4, math.sqrt(scale)
        back = ""
        if self.given_back > 0:
            back = (f" (not counting {self.given_back * energy:.3g} J of springs and servos whose "
                    "stiffness and rest never change: they only give back what they stored)")  # fmt: skip
        return (
            f"the total energy rose from {self.before * energy:.4g} J at t = {self.t0 * tick:.4f} "
            f"s to {self.after * energy:.4g} J at t = {self.t1 * tick:.4f} s "
            f"({'one sample' if n == 1 else f'{n} samples'}"
            f" later) with only {self.work * energy:.3g} J of actuator work between{back}, and "
            "nothing else in a creature adds energy"
        )


def energy_floor(traj: Trajectory) -> float:
    """The least energy scale: ``FLOOR`` times the creature's weight times its height at the
    start (its centre of mass over z = 0, or its longest leg; at least ``FLOOR_HEIGHT``)."""
    if not len(traj):
        return 0.0
    heights = [abs(float(traj.com[0, 2])), *traj.leg_length[0].tolist(), FLOOR_HEIGHT]
    return FLOOR * traj.total_mass * traj.gravity * max(h for h in heights if np.isfinite(h))


def rises(traj: Trajectory, held: Sequence[HeldSpring] = ()) -> list[EnergyRise]:
    """For each window length (1 to ``WINDOW`` samples), its largest rise past the bound, the
    ``held`` springs' work and what they hold no source; none for a recording without the
    actuators' work (an older legdsl's)."""
    n = len(traj)
    if n < 2 or traj.work_positive.shape[0] != n:
        return []
    total = traj.kinetic + traj.potential + traj.elastic
    live = traj.kinetic + traj.elastic
    sources = np.ones(traj.work_positive.shape[1], dtype=bool)
    stored = traj.elastic.copy()  # what the springs whose settings may change hold
    for spring in held:
        sources[spring.index] = False
        stored -= spring.holds(traj.q)
    work = traj.work_positive[:, sources].sum(axis=1)
    back = traj.work_positive[:, ~sources].sum(axis=1)
    finite = np.isfinite(total) & np.isfinite(live) & np.isfinite(work) & np.isfinite(stored)
    # the most energy in motion and in the springs up to each sample, and the floor
    scale = np.maximum.accumulate(np.where(finite, live, 0.0)) + energy_floor(traj)
    found = []
    for lag in range(1, min(WINDOW, n - 1) + 1):
        # a state past doubles (a start 1e308 m up) makes inf - inf here: masked just below
        with np.errstate(invalid="ignore", over="ignore"):
            worked = work[lag:] - work[:-lag]
            past = total[lag:] - total[:-lag] - worked - stored[lag:]
            room = scale[:-lag] + SLACK * worked  # > 0 but for a weightless creature at rest
            ratio = np.divide(past, room, out=np.zeros(n - lag), where=room > 0)
        ratio[~(finite[lag:] & finite[:-lag])] = -np.inf
        a = int(np.argmax(ratio))
        b = a + lag
        found.append(EnergyRise(a, b, float(traj.t[a]), float(traj.t[b]), float(total[a]),
                                float(total[b]), float(work[b] - work[a]), float(ratio[a]),
                                float(back[b] - back[a])))  # fmt: skip
    return found


def unexplained_rise(traj: Trajectory, held: Sequence[HeldSpring] = ()) -> EnergyRise | None:
    """The rise past the bound by more than ``RISE`` times the energy scale in the shortest
    window that has one (the largest there), or None; the ``held`` springs are no source."""
    return next((r for r in rises(traj, held) if r.ratio > RISE), None)


def told(sim: Any, result: RunResult) -> RunResult:
    """``result`` of ``sim`` (a ``legdsl.sim.simulate.Simulation``, at the run's end), a run
    that ended ok or fell, told as a divergence if its energy rose without a source: the
    rise, its likely cause and how the run went on. Else, and for a run diverged or
    interrupted already, as it is."""
    if result.status not in ("ok", "fell"):
        return result
    try:
        rise = unexplained_rise(result.trajectory, held_springs(sim))
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
    if unexplained_rise(run.head(int(last[-1]) + 1), held_springs(sim)) is not None:
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
