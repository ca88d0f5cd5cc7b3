"""Why a run diverged, told at a pose with what the creature's dynamics says there.

``legdsl.sim.stability.likely_cause`` weighs the causes; this module gathers what it needs
from a ``legdsl.sim.simulate.Simulation``: the mass matrix at a singular pose, the actuators
and joint stops too stiff for the step, and each contact's effective masses under the
ground's springs (``contact_inverse_masses``), which a light leg's tip, turning about the
leg's centre of mass, can have far under its body's mass.
"""

from __future__ import annotations

import contextlib
from collections.abc import Sequence
from typing import Any

import numpy as np

from legdsl.sim.stability import inverse_inertia_diagonal, likely_cause, stiff_now
from legdsl.sim.trajectory import Trajectory


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
) -> str:
    """``likely_cause`` at pose ``q`` (the state a divergence stopped at, or the sample an
    energy rise started from), with what the ``run`` recorded up to it. A division by zero
    may be the dynamics' own, at a singular mass matrix, so that is looked at too; the
    actuators are checked at their settings now and the inertia of the initial pose, the
    contacts at the last finite sample recorded (a diverged state's pose is any)."""
    model, opts = sim.model, sim.options
    mass = None
    if isinstance(err, ZeroDivisionError):
        with contextlib.suppress(ArithmeticError, ValueError):
            mass = sim.dyn.mass_matrix(list(q))
    stiff: list[str] = []
    with contextlib.suppress(ArithmeticError, ValueError):  # the inertia of the initial pose
        inverse = inverse_inertia_diagonal(sim.dyn.mass_matrix(list(model.q0)))
        stiff = stiff_now(sim.actuators.states, model.stops, inverse, opts.dt, opts.integrator)
    pose = list(model.q0)
    if run is not None and len(run):
        finite = np.flatnonzero(np.all(np.isfinite(run.q), axis=1))
        if len(finite):
            pose = run.q[finite[-1]].tolist()
    contacts = contact_inverse_masses(sim, pose)
    return likely_cause(model, opts.dt, opts.integrator, q, mass, stiff, run, contacts)
