"""What a run's actuators spent: their positive work, per metre and as a cost of transport.

The simulator sums each actuator's mechanical power ``tau * qd`` (its force or torque times
its coordinate's rate) at every integration step, the positive part and the negative part
apart, and records the running sums (``Trajectory.work_positive``, ``work_negative``). Over
the metrics window, from its first sample to its last:

- **positive actuator work** ``W`` (J): the sum over the actuators of the rise of their
  positive work. Negative work (an actuator braking its joint, a spring taking up energy)
  does not pay any of it back: the usual cost of transport counts positive mechanical work
  only, as a motor spends energy to do positive work and gets none back for braking.
- **distance** ``d`` (m): the length of the path of the centre of mass in the horizontal
  plane, sample to sample (a path that turns counts its length, not its chord).
- **energy per metre** ``W / d`` (J/m), and the dimensionless **cost of transport**
  ``W / (m g d)`` with ``m`` the creature's mass and ``g`` gravity; n/a for a creature whose
  root body never moves over the ground (welded to the world: a test rig's centre of mass
  sways with its limbs, but it goes nowhere), and for one whose centre of mass went less than
  a millionth of its height (``STILL``): a trot in place summed 2.7e-15 m of rounding, and
  its work per metre read 1.3e17 J/m.

A spring actuator's ``tau * qd`` is the power at its joint, so its positive work includes the
recoil of the spring, which a real spring returns for free: for the air-spring legs of the
hopper and the kangaroo, the figure is the work a motor in the spring's place would do, an
upper bound on what the leg's actuator must supply. The net work (positive plus negative) is
recorded too, for an energy balance.
"""

from __future__ import annotations

import math

import numpy as np

from legdsl.analysis.results import Summary
from legdsl.analysis.strides import EPS_T
from legdsl.sim.trajectory import Trajectory

STILL = 1e-6  # of the centre of mass's height: a horizontal path shorter than this is no move
KEYS = ("positive_work", "negative_work", "distance", "energy_per_metre", "cost_of_transport")


def window_work(tr: Trajectory, t_from: float, t_to: float) -> tuple[np.ndarray, np.ndarray, int]:
    """Each actuator's positive and negative work from the window's first sample to its last,
    and how many samples the window holds (work of zeros when it holds fewer than two)."""
    inside = np.flatnonzero((tr.t >= t_from - EPS_T) & (tr.t <= t_to + EPS_T))
    na = tr.work_positive.shape[1]
    if inside.size < 2:
        return np.zeros(na), np.zeros(na), int(inside.size)
    a, b = inside[0], inside[-1]
    return (tr.work_positive[b] - tr.work_positive[a],
            tr.work_negative[b] - tr.work_negative[a], int(inside.size))  # fmt: skip


def horizontal_distance(tr: Trajectory, t_from: float, t_to: float) -> float:
    """The length of the centre of mass's horizontal path in the window (m)."""
    inside = (tr.t >= t_from - EPS_T) & (tr.t <= t_to + EPS_T)
    xy = tr.com[inside, :2]
    return float(np.sum(np.hypot(*np.diff(xy, axis=0).T))) if len(xy) > 1 else 0.0


def went_somewhere(tr: Trajectory, distance: float, t_from: float, t_to: float) -> bool:
    """Whether the centre of mass's horizontal path is more than rounding: longer than
    ``STILL`` of its mean height in the window, and its root not welded to the world."""
    if len(tr) == 0 or not np.any(np.ptp(tr.root_pos[:, :2], axis=0)):
        return False
    inside = (tr.t >= t_from - EPS_T) & (tr.t <= t_to + EPS_T)
    height = float(np.mean(np.abs(tr.com[inside, 2]))) if np.any(inside) else 0.0
    return distance > STILL * (height or 1.0)


def energy_rows(tr: Trajectory, t_from: float, t_to: float) -> list[Summary]:
    """The energy rows of the metrics (none for a run recorded before work was)."""
    if tr.extra.get("unrecorded"):
        return []
    positive, negative, n = window_work(tr, t_from, t_to)

    def total(key: str, label: str, value: float) -> Summary:
        return Summary(key, label, value if n > 1 else math.nan, math.nan, n, "total")

    work = float(np.sum(positive))
    distance = horizontal_distance(tr, t_from, t_to)
    per_metre = work / distance if went_somewhere(tr, distance, t_from, t_to) else math.nan
    weight = tr.total_mass * tr.gravity
    rows = [
        total("positive_work", "positive actuator work (J)", work),
        total("negative_work", "negative actuator work (J)", float(np.sum(negative))),
    ]
    if len(tr.actuator_names) > 1:
        rows += [
            total(f"positive_work_{name}", f"positive work, {name} (J)", float(w))
            for name, w in zip(tr.actuator_names, positive, strict=True)
        ]
    return rows + [
        total("distance", "horizontal distance of the centre of mass (m)", distance),
        total("energy_per_metre", "positive actuator work per metre (J/m)", per_metre),
        total(
            "cost_of_transport",
            "cost of transport, work / (m g d) (-)",
            per_metre / weight if weight > 0 else math.nan,
        ),  # fmt: skip
    ]
