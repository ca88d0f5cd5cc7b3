"""Why a run diverged, told at a pose with what the creature's dynamics says there.

``legdsl.sim.stability.likely_cause`` weighs the causes; this module gathers what it needs
from a ``legdsl.sim.simulate.Simulation``: the mass matrix at a singular pose, the actuators
and joint stops too stiff for the step, and each contact's effective masses under the
ground's springs (``contact_inverse_masses``), which a light leg's tip, turning about the
leg's centre of mass, can have far under its body's mass. A foot that was down and slid
under a step's or box's top edge (``under_edge``) is found from the feet's positions at the
last few samples, which the recording has not: from its poses, with the dynamics.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from legdsl.ir.model import Pad
from legdsl.sim.absurd_settings import absurd_setting
from legdsl.sim.contact import pad_force
from legdsl.sim.coupled import inverse_inertia
from legdsl.sim.recorder import TooFast
from legdsl.sim.stability import (
    CLEAR_IT,
    PUSHED,
    TOPS_ONLY,
    ground_too_stiff,
    likely_cause,
    stiff_now,
)
from legdsl.sim.trajectory import Trajectory

# The ground under a foot that rose by more than this share of the lowest step's or box's
# height between two samples went under a top's edge; the last this many samples are looked at.
EDGE = 0.1
EDGE_SAMPLES = 4
# Touchdowns since this many finite samples before the stop, and at least this long (s), are
# looked at (``touched_deep``): the last three samples at the default rate, at any rate.
DEEP_SAMPLES = 3
DEEP_WINDOW = 0.015


def contact_inverse_masses(sim: Any, q: Sequence[float]) -> list[tuple[float, float]] | None:
    """Each contact's inverse effective mass (1/kg) along the ground's normal under it and
    along its tangents (the lightest tangent), at pose ``q``: ``d^T J M^-1 J^T d`` for each
    direction ``d``; None without a ground, or where the dynamics cannot give it."""
    if sim.ground is None or not sim.contact_names:
        return None
    try:
        inverse = np.linalg.inv(np.asarray(sim.dyn.mass_matrix(list(q)), dtype=float))
        jacobians = sim.dyn.contact_jacobians(list(q))
        positions = sim.dyn.contact_positions(list(q))
    except (ArithmeticError, ValueError, np.linalg.LinAlgError):
        return None
    masses = []
    for jacobian, p in zip(jacobians, positions, strict=True):
        j = np.asarray(jacobian, dtype=float)
        a = j @ inverse @ j.T  # the contact point's inverse inertia, 3 x 3 (1/kg)
        normal, *tangents = (np.asarray(d, dtype=float) for d in sim.ground.directions(p))
        masses.append((float(normal @ a @ normal), max(float(t @ a @ t) for t in tangents)))
    return masses if np.all(np.isfinite(masses)) else None


def cause_at(
    sim: Any,
    q: Sequence[float],
    err: BaseException | None = None,
    run: Trajectory | None = None,
    through: Trajectory | None = None,
    otherwise: str | None = None,
) -> str:
    """``likely_cause`` at pose ``q`` (the state a divergence stopped at, or the sample an
    energy rise started from), with what the ``run`` recorded up to it. A division by zero
    may be the dynamics' own, at a singular mass matrix, so that is looked at too; the
    actuators are checked at their settings now and the inertia of the initial pose, the
    contacts at the last finite sample recorded (a diverged state's pose is any). A foot
    pushed under a step's edge is looked for in ``through`` (what the run recorded past ``q``,
    up to an energy rise's end, where the push is; ``run`` if None); ``otherwise`` is told
    if nothing is found."""
    if isinstance(err, TooFast) and sim.t == 0.0:  # before the first step: nothing else is
        return start_speed(sim, err)
    model, opts, scale = sim.model, sim.options, sim.size_scale  # told as --scale L's creature
    mass = None
    if isinstance(err, ZeroDivisionError):
        with contextlib.suppress(ArithmeticError, ValueError):
            mass = sim.dyn.mass_matrix(list(q))
    stiff: list[str] = []
    with contextlib.suppress(ArithmeticError, ValueError):  # the inertia of the initial pose
        inverse = inverse_inertia(model, sim.dyn.mass_matrix, model.q0)
        stiff = stiff_now(model, sim.actuators.states, inverse, opts.dt, opts.integrator, scale,
                          sim.step_flags)  # fmt: skip
    pose = list(model.q0)
    if run is not None and len(run):
        finite = np.flatnonzero(np.all(np.isfinite(run.q), axis=1))
        if len(finite):
            pose = run.q[finite[-1]].tolist()
    contacts = contact_inverse_masses(sim, pose)
    edge = under_edge(sim, through if through is not None else run)
    found = [edge] if edge is not None else []
    absurd = absurd_setting(sim, pose)  # a rest or setpoint the controller set past reason
    if absurd is not None:
        found.insert(0, absurd)
    # A touchdown far under the surface, from the contacts' own events (the samples may miss
    # it); the recorded samples' look (``likely_cause``'s) is then not asked again.
    ground = ground_too_stiff(model, opts.dt, opts.integrator, contacts, scale, sim.step_flags)
    deep = touched_deep(sim, run) if ground is None else None
    if deep is not None:
        found.append(deep)
    return likely_cause(model, opts.dt, opts.integrator, q, mass, stiff,
                        run if deep is None else None, contacts, found, scale, otherwise,
                        sim.step_flags)  # fmt: skip


def touched_deep(sim: Any, run: Trajectory | None) -> str | None:
    """A foot that touched down far under the surface (the ground pushing it past ``PUSHED``
    weights at its touchdown), judged from the ground's touchdown events since the last
    ``DEEP_SAMPLES`` finite samples or ``DEEP_WINDOW`` (a foot running into a box's side between two samples
    touched down, and may have been thrown out and the run blown up, before the next one):
    the push recorded at the touchdown's own step where it was sampled, else the ground's
    spring alone at the depth the foot reached, moved on from the sample before at the
    velocity it had there. The first such push, as ``legdsl.sim.stability``'s cause in its
    words; None if there was none."""
    model = sim.model
    weight = model.total_mass * abs(model.gravity[2])
    g = model.ground
    if run is None or sim.ground is None or g is None or not weight > 0 or not len(run):
        return None
    finite = np.flatnonzero(np.all(np.isfinite(run.q), axis=1) & np.all(np.isfinite(run.v), axis=1))
    if not len(finite):
        return None
    since = float(run.t[finite[max(0, len(finite) - DEEP_SAMPLES)]])
    since = min(since, float(run.t[finite[-1]]) - DEEP_WINDOW)
    names = list(sim.contact_names)
    found: tuple[float, str, float, str] | None = None
    for e in sim.events:
        if e.kind != "touchdown" or e.t <= since or e.contact not in names:
            continue
        c = names.index(e.contact)
        at = [i for i in finite if abs(run.t[i] - e.t) < 1e-9 and run.contact[i, c] != 0]
        if at and np.all(np.isfinite(run.force[at[0], c])):
            push, how = float(np.linalg.norm(run.force[at[0], c])), ""
        else:
            before = [i for i in finite if run.t[i] < e.t - 1e-12]
            if not before or run.contact[before[-1], c] != 0:
                continue
            a = before[-1]
            try:
                q, v = run.q[a].tolist(), np.asarray(run.v[a], dtype=float)
                p = np.asarray(sim.dyn.contact_positions(q)[c], dtype=float)
                j = np.asarray(sim.dyn.contact_jacobians(q)[c], dtype=float)
                depth = sim.ground.depth(tuple(p + (j @ v) * (e.t - float(run.t[a]))))[0]
            except (ArithmeticError, ValueError, IndexError):
                continue
            normal = g.normal
            spring = pad_force(normal, depth) if isinstance(normal, Pad) else normal.k * depth
            push = spring if depth > 0 else 0.0
            how = (f" at least (its spring alone, {depth * sim.size_scale * 100:.3g} cm under "
                   "the surface)")  # fmt: skip
        if push > PUSHED * weight:  # the first: the later ones follow from it
            found = (push, how, e.t, e.contact)
            break
    if found is None:
        return None
    push, how, t, name = found
    said = (
        f"contact '{name}' touched down far under the surface: the ground pushed it with "
        f"{push * sim.size_scale**3:.3g} N{how} at t = {t * math.sqrt(sim.size_scale):.4f} s, "
        f"{push / weight:.0f} times the creature's weight"
    )
    if any(f.kind in ("step", "box") for f in g.terrain):
        return f"{said}, as a foot that runs into the side of a step or box does ({TOPS_ONLY}); {CLEAR_IT}"
    return f"{said}; land softer (a slower approach, a softer leg) or give the ground a pad"


def under_edge(sim: Any, run: Trajectory | None) -> str | None:
    """A foot down already whose ground rose abruptly under it (by more than ``EDGE`` of the
    lowest step's or box's height, between two of the last ``EDGE_SAMPLES`` samples) and that
    the ground pushed past ``PUSHED`` weights: it slid under a top's edge, and is under the top
    at once (the ground has no side faces). The push is the one recorded where the foot is down
    still; where it was thrown out between the samples, the least it was: the ground's spring
    alone at the depth under the top the foot was at before. The largest such push, as a
    cause; None if there was none, or no step or box."""
    model = sim.model
    g = model.ground
    flats = [f for f in g.terrain if f.kind in ("step", "box")] if g is not None else []
    weight = model.total_mass * abs(model.gravity[2])
    if (
        g is None
        or run is None
        or sim.ground is None
        or not flats
        or not weight > 0
        or not run.force.shape[1]
    ):
        return None
    finite = np.all(np.isfinite(run.q), axis=1)
    rows = np.flatnonzero(finite & np.all(np.isfinite(run.force.reshape(len(run), -1)), axis=1))
    rows = rows[-EDGE_SAMPLES:]
    try:
        feet = [sim.dyn.contact_positions(run.q[i].tolist()) for i in rows]
        ground = [[sim.ground.height(p[0], p[1]) for p in at] for at in feet]
    except (ArithmeticError, ValueError):
        return None
    least = EDGE * min(abs(f.get("height")) for f in flats)
    normal = g.normal
    found = None
    for k in range(1, len(rows)):
        a, b = rows[k - 1], rows[k]
        for c, name in enumerate(sim.contact_names):
            rose = ground[k][c] - ground[k - 1][c]
            if b != a + 1 or run.contact[a, c] == 0 or not rose > least:
                continue
            if run.contact[b, c] != 0:
                push, least_, how = float(np.linalg.norm(run.force[b, c])), "", ""
            else:  # thrown out between the samples
                depth = ground[k][c] - feet[k - 1][c][2]
                spring = pad_force(normal, depth) if isinstance(normal, Pad) else normal.k * depth
                push = spring if depth > 0 else 0.0
                least_ = (f" at least (its spring alone, {depth * sim.size_scale * 100:.3g} cm "
                          "under the top)")  # fmt: skip
                how = ", and was thrown out"
            if push > PUSHED * weight and (found is None or push > found[0]):
                found = (push, least_, how, name, rose, float(run.t[a]), float(run.t[b]))
    if found is None:
        return None
    push, least_, how, name, rose, t0, t1 = found
    scale, tick = sim.size_scale, math.sqrt(sim.size_scale)  # a --scale L run's creature
    kinds = sorted({f.kind for f in flats}, reverse=True)  # step, box
    return (
        f"contact '{name}' went under the edge of a {' or '.join(kinds)} (the ground under it "
        f"rose {rose * scale * 100:.3g} cm between t = {t0 * tick:.4f} s and t = "
        f"{t1 * tick:.4f} s) and was pushed with {push * scale**3:.3g} N{least_}, "
        f"{push / weight:.0f} times the creature's weight{how}; "
        f"{TOPS_ONLY}; {CLEAR_IT}"
    )


def start_speed(sim: Any, err: TooFast) -> str:
    """A speed past the limit before the first step: the start velocity the file gives, which
    no step or integrator changes (a root pushed at 1200 m/s was told to try a smaller step or
    rk4, and told so again after both). Told as a --scale L run's creature, with the bound its
    file's line, the unscaled creature's, should stay below."""
    k, by = err.index, sim.v_factors[err.index]
    unit = "rad/s" if sim.model.v_angular[k] else "m/s"
    name, speed, most = sim.model.v_names[k], err.speed * by, err.limit * by
    given, bound = f"{name} = {speed:.4g} {unit}", f"{most:.4g} {unit}"
    if by != 1.0:
        given += f", as --scale {sim.size_scale:g} makes the file's {err.speed:.4g} {unit}"
        bound = f"{err.limit:.4g} {unit} there ({bound} scaled)"
    return (
        f"nothing grew without bound: the creature starts at this speed, the start velocity "
        f"its file gives ({given}), which no step or integrator changes; the limit is the "
        f"divergence rule's for a creature of its size (docs/runtime.md#divergence-and-falls): "
        f"give its `velocity` a speed under {bound}"
    )
