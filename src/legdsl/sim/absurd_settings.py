"""A spring's rest or a servo's setpoint that the controller set to a number no creature could
mean, as a divergence's cause, named at the controller's statement that sets it.

A huge value passed to an action (``relax(active, 1e308 m)``, ``hop_apex(..., -1e308 * stroke,
1)``) is finite, so the control law does not fail; the actuator's force ``k (rest - q)``
overflows, or pushes the creature past the divergence speed within one step, and the state
is no longer finite. It was told as "the state grew without bound; try a smaller step or
--integrator rk4", which no step cures. ``absurd_setting`` finds such a setting at the stop:
a target more than ``FAR`` of the creature's standing heights (a length) or ``TURNS`` turns (an
angle) from its coordinate, or whose force (as the actuator's ``max`` clips it) is not finite
or gives the creature's whole mass more than the divergence speed in one step; and the
statements of the controller that set it (``file:line:col``, and the action calls it was
inlined through), the one of the state the run stopped in first.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Sequence
from typing import Any

from legdsl.sim.sizes import divergence_speed

FAR = 1e3  # standing heights: a rest or setpoint (a length) this far from its coordinate
TURNS = 1e3  # turns: a rest or setpoint (an angle) this far from its coordinate


def absurd_setting(sim: Any, pose: Sequence[float]) -> str | None:
    """The first spring or servo whose rest or setpoint the run stopped with is absurd (see
    the module docstring), told with the value, why, and the controller's statements that
    set it; None if there is none, or no controller sets it."""
    model = sim.model
    height = 1.0
    with contextlib.suppress(ArithmeticError, ValueError, TypeError):
        height = max(sim.standing_height(list(model.q0)), 1e-3)
    weight_mass = model.total_mass
    limit = divergence_speed(height)
    dt = sim.options.dt
    rotary = {a.name: a.rotary for a in model.actuators}
    for a in sim.actuators.states:
        if a.kind not in ("spring", "servo"):
            continue
        turn = rotary.get(a.name, False)
        q = pose[a.q_index] if a.q_index < len(pose) and math.isfinite(pose[a.q_index]) else 0.0
        stretch = a.target - q
        force = a.gain * stretch if math.isfinite(stretch) else math.inf
        if a.limit is not None and math.isfinite(force):
            force = max(-a.limit, min(a.limit, force))
        reach = TURNS * math.tau if turn else FAR * height
        inertia = weight_mass * (height**2 if turn else 1.0)
        why = ""
        if not abs(stretch) <= reach:
            scale = "turns" if turn else "times the creature's standing height"
            size = abs(stretch) / (math.tau if turn else height)
            why = f"{size:.3g} {scale} from its coordinate"
        if not math.isfinite(force):
            why = (why + ", and" if why else "") + " its force k (target - coordinate) overflows"
        elif inertia > 0 and abs(force) * dt / inertia > limit and why:
            why += f", and its force, {abs(force):.3g} {'N*m' if turn else 'N'}, is past any"
            why += " the creature could take in a step"
        if not why:
            continue
        setting = "rest" if a.kind == "spring" else "setpoint"
        unit = "rad" if turn else "m"
        where = setters(sim, a.name, setting)
        at = f" at {where}" if where else ""
        return (
            f"the controller set {a.name}.{setting} = {a.target * (1.0 if turn else sim.size_scale):.4g} "
            f"{unit}{at}: {why.strip(', ')}, a value no step or integrator can follow; bound "
            f"what that statement is given (its action's arguments there) to what the "
            f"creature can reach"
        )
    return None


def setters(sim: Any, actuator: str, setting: str) -> str:
    """Where the controller sets ``actuator.setting``: 'file:line:col (inlined ...)', the
    statement of the state the run is in where it sets it, else those of the others (at most
    three); '' where
    the controller cannot be lowered again or no statement sets it."""
    machine = getattr(sim, "controller", None)
    module = getattr(machine, "module", None)
    if module is None:
        return ""
    try:
        from legdsl.lower.control import Lowerer
        from legdsl.sim.control_faults import _where

        lc = Lowerer(sim.model, sim.model.controller(module.CONTROLLER)).lower()
    except Exception:  # explaining must never hide the divergence itself
        return ""
    now = (getattr(machine, "binding", -1), getattr(machine, "state_index", -1))
    found: list[str] = []
    for key in sorted(lc.bodies, key=lambda k: k != now):
        for st in lc.bodies[key].settings:
            if st.actuator == actuator and st.key == setting and _where(st.where) not in found:
                found.append(_where(st.where))
        if key == now and found:  # the state the run is in sets it: that statement did
            return found[0]
    return "; or at ".join(found[:3])
