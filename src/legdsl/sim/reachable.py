"""A speed past the divergence rule's limit that the creature's own energy reaches.

The divergence rule's limit is fixed (``legdsl.sim.sizes``); a creature whose springs, fall or
actuators give it the energy for a speed past it reaches it in its own motion, however soon
(a pendulum on a stiff spring, in its first step), where no step or integrator changes
anything. ``reachable_speed`` tells that from the energy balance at the state now, not from
the last sample recorded (``legdsl.sim.energy_check.own_speed``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from legdsl.sim.energy_check import held_springs, unexplained_rise
from legdsl.sim.recorder import TooFast
from legdsl.sim.trajectory import Trajectory

# A speed past the divergence limit with a total energy no more than what the creature had
# (at the start, and from its actuators that are sources) by REACH - 1 times what it had to
# move with is its own: energy is conserved but for what those actuators give, and a step
# blowing up makes it, leaping far past this within a few steps (a semi-implicit step near
# its stability bound overshoots the motion's energy by a part).
REACH = 1.5


def reachable_speed(sim: Any, err: BaseException | None, run: Trajectory | None) -> str | None:
    """A speed past the divergence rule's fixed limit (``err``, at the state now of ``sim``,
    which recorded ``run`` from its start with no energy rise without a source) that the
    creature's energy reaches: its total energy now (in motion, in its springs, the ground's
    and its height) is no more than it started with and its actuators gave (the springs that
    no controller changes and that have no ``max`` give back only what they held; the others
    may hold more, moved), by ``REACH`` - 1 times the energy it had to move with, so nothing
    grew without bound, however soon the speed came (a pendulum on a 1e8 N*m/rad
    spring 10 deg from its rest reaches 1513 rad/s, past the limit in its first step at 0.1 ms;
    it was told to try a smaller step or rk4). Told with where the energy came from, and the
    speed it allows; None for any other divergence, or where the dynamics cannot tell."""
    if not isinstance(err, TooFast) or run is None or not len(run) or sim.t == 0.0:
        return None
    q, k = list(sim.q), err.index
    try:
        kinetic, potential, elastic = sim.energy()
        inverse = np.linalg.inv(np.asarray(sim.dyn.mass_matrix(q), dtype=float))
    except (ArithmeticError, ValueError, np.linalg.LinAlgError):
        return None
    held = {h.index for h in held_springs(sim)}
    bank = sim.actuators
    work = math.fsum(w for i, w in enumerate(bank.positive_work) if i not in held)
    moving, springs, height = (float(x[0]) for x in (run.kinetic, run.elastic, run.potential))
    fall = height - potential
    available = moving + springs + fall + work
    reach = 2.0 * available * float(inverse[k, k])
    if not (math.isfinite(kinetic) and available > 0 and reach > 0):
        return None
    moved = bank.elastic_energy(
        q, tuple(a.name for i, a in enumerate(bank.states) if i not in held)
    )
    grew = kinetic + potential + elastic - (moving + springs + height + work + moved)
    if not grew <= (REACH - 1.0) * available:
        return None
    if len(run) > 1 and unexplained_rise(run, held_springs(sim)) is not None:
        return None
    model, tick, scale = sim.model, math.sqrt(sim.size_scale), sim.size_scale
    joules = scale**4  # an energy's factor for a --scale L run's creature (kg m^2 / s^2)
    unit, by = ("rad/s" if model.v_angular[k] else "m/s"), sim.v_factors[k]
    start = run.q[0].tolist()
    held_at_start = {s.name: bank.elastic_energy(start, (s.name,)) for s in bank.states}
    sources = []
    if springs > 0.01 * available:
        most = max(held_at_start, key=lambda n: held_at_start[n], default=None)
        whose = ""
        if most is not None and held_at_start[most] > 0.5 * springs:
            whose = f" ({held_at_start[most] * joules:.3g} J of it in '{most}')"
        sources.append(f"its springs held {springs * joules:.3g} J at the start{whose}")
    if fall > 0.01 * available:
        sources.append(f"it fell by {fall * joules:.3g} J of gravitational energy")
    if moving > 0.01 * available:
        sources.append(f"it started with {moving * joules:.3g} J in motion")
    if work > 0.01 * available:
        sources.append(f"its actuators did {work * joules:.3g} J of work")
    spring = bool(sources) and sources[0].startswith("its springs")
    how = "in its own motion"
    finite = np.flatnonzero(np.all(np.isfinite(run.com_vel), axis=1))
    if unit == "m/s" and len(finite) and fall > 0.5 * available:
        down = -float(run.com_vel[finite[-1], 2]) * tick
        how = f"falling ({down:.3g} m/s down at its centre of mass)"
    advice = (
        "a softer spring, or one started nearer its rest, keeps the motion under the limit"
        if spring
        else "a slower motion keeps under it"
    )
    return (
        f"nothing grew without bound: the creature reached this speed {how}: "
        f"{'; '.join(sources) or 'from its start'}: {available * joules:.3g} J in all to move "
        f"with, "
        f"enough for {model.v_names[k]} to reach {math.sqrt(reach) * by:.4g} {unit} (its energy "
        f"in motion now is {kinetic * joules:.3g} J); a step or an integrator changes nothing "
        f"here: the limit, {err.limit * by:.4g} {unit}, is the divergence rule's for a creature "
        f"of its size (docs/runtime.md#divergence-and-falls), and {advice}. What was recorded "
        f"up to here stands; a --time under {sim.t * tick:.4g} s ends the run before it"
    )
