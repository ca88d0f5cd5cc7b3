"""Recording a simulation: the trajectory's rows, one per recorded instant (``legdsl.sim.trajectory``
holds them; ``legdsl.sim.simulate`` decides when)."""

from __future__ import annotations

import math
import os
from typing import Any

from legdsl.ir.model import Model
from legdsl.sim.sensors import rpy
from legdsl.sim.trajectory import Trajectory, empty


class Divergence(Exception):
    """The simulation diverged: its state stopped being finite, or a step blew up."""


class TooFast(Divergence):
    """A velocity past the divergence rule's limit: v[``index``] at ``speed``, over ``limit``
    (the model's numbers)."""

    def __init__(self, message: str, index: int, speed: float, limit: float) -> None:
        super().__init__(message)
        self.index, self.speed, self.limit = index, speed, limit


def empty_trajectory(sim: Any, capacity: int) -> Trajectory:
    """An empty recording of ``capacity`` rows for a ``legdsl.sim.simulate.Simulation``."""
    m = sim.model
    return empty(
        capacity,
        sim.dyn.NQ,
        sim.dyn.NV,
        len(sim.contact_names),
        len(m.legs),
        len(sim.actuators.states),
        q_names=m.q_names,
        v_names=m.v_names,
        contact_names=sim.contact_names,
        leg_names=tuple(leg.name for leg in m.legs),
        leg_feet=tuple(sim._foot),
        leg_soles=tuple(tuple(sim.contact_names.index(c) for c in leg.soles) for leg in m.legs)
        if any(leg.more_soles for leg in m.legs)
        else (),
        state_names=sim.controller.state_names if sim.controller else (),
        actuator_names=tuple(s.name for s in sim.actuators.states),
        total_mass=m.total_mass,
        gravity=-m.gravity[2],
        planar=m.planar,
    )


def sample_bytes(model: Model) -> int:
    """The memory one recorded sample of ``model``'s run takes (every array of its row)."""
    nc, nl, na = len(model.contacts), len(model.legs), len(model.actuators)
    return empty(0, model.nq, model.nv, nc, nl, na).row_bytes()


def recording_budget() -> int | None:
    """The most memory a run's recording may take: half the machine's, and under a limit of
    the process's address space (``ulimit -v``) half of what is left of it (None where the
    system says neither). Past it the system would kill the run, or Python fail to grow the
    recording, with nothing written."""
    try:
        budget: int | None = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") // 2
    except (AttributeError, ValueError, OSError):
        budget = None
    left = address_space_left()
    if left is not None:
        budget = left // 2 if budget is None else min(budget, left // 2)
    return budget


def address_space_left() -> int | None:
    """Bytes of address space the process may still take under ``ulimit -v`` (None: no
    limit, or a system that does not say how much it has taken)."""
    try:
        import resource

        limit = resource.getrlimit(resource.RLIMIT_AS)[0]
        if limit == resource.RLIM_INFINITY:
            return None
        with open("/proc/self/statm", encoding="ascii") as statm:  # its first field: pages
            taken = int(statm.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
    except (ImportError, OSError, ValueError, IndexError):
        return None
    return max(0, limit - taken)


def record_row(sim: Any, traj: Trajectory, row: int) -> None:
    """Row ``row`` of ``traj``: the simulation's state now, and what follows from it."""
    dyn, q, v = sim.dyn, sim.q, sim.v
    if not all(math.isfinite(x) for x in q) or not all(math.isfinite(x) for x in v):
        raise Divergence("the state is no longer finite (NaN or infinity)")  # not recorded
    traj.t[row] = sim.t
    traj.q[row] = q
    traj.v[row] = v
    if sim.ground is not None and sim.contact_names:  # [] is no (0, 3) array
        traj.contact[row] = sim.ground.touching
        traj.force[row] = sim.contact_force
    traj.com[row] = dyn.center_of_mass(q)
    traj.com_vel[row] = dyn.center_of_mass_velocity(q, v)
    poses = dyn.body_poses(q)
    pos, rot = poses[0]
    traj.root_pos[row] = pos
    traj.root_rpy[row] = rpy(rot, sim.model.planar)
    if sim._hips:
        feet = dyn.contact_positions(q)
        for i, (hip, foot) in enumerate(zip(sim._hips, sim._foot, strict=True)):
            traj.leg_length[row, i] = math.dist(hip.point(poses), feet[foot])
            traj.leg_spring_energy[row, i] = sim.actuators.elastic_energy(q, sim._leg_springs[i])
    kinetic, potential, elastic = sim.energy()
    traj.kinetic[row] = kinetic
    traj.potential[row] = potential
    traj.elastic[row] = elastic
    if sim.controller is not None:
        traj.state[row] = sim.controller.state_index
        traj.speed_command[row] = sim.controller.speed_command(sim.t)
    traj.work_positive[row] = sim.actuators.positive_work
    traj.work_negative[row] = sim.actuators.negative_work
