"""The foot's speed over the ground at touchdown: a metric that needs the creature's kinematics.

Ground speed matching (raibert's ``place_two_link_matched``, ``place_foot_matched``) swings the
foot back late in flight so that it lands moving with the ground; how well it does is the
speed of each leg's foot contact along the ground (horizontal on flat ground and on the tops of
steps and boxes, along the tilted surface on a slope) just before its
touchdown, at the last recorded sample of the flight (so within one record interval of it:
5.2 ms at the default 200 Hz, one integration step with ``--record-rate 0 Hz``). The contact
velocities are recomputed with the creature's generated dynamics module, as the apex
clearance is (``legdsl.pipeline.apex``); a run made with ``--scale L`` is measured as the
scaled creature (speeds by L^(1/2)).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from legdsl.analysis.results import Summary
from legdsl.analysis.rows import stat
from legdsl.analysis.strides import runs
from legdsl.pipeline.apex import Kinematics
from legdsl.pipeline.scaled import v_factors
from legdsl.pipeline.terrain_rows import model_ground_normal
from legdsl.sim.trajectory import Trajectory

KEY = "touchdown_foot_speed"
LABEL = "foot speed over the ground at touchdown (m/s)"


def touchdown_speed_row(
    found: Kinematics, tr: Trajectory, t_from: float, t_to: float | None
) -> Summary:
    """The mean over the legs' touchdowns in the window, measured with the run's creature."""
    model, dyn, q_f, scale = found
    v_f = v_factors(model, scale)
    normal = model_ground_normal(model)  # level everywhere but on a slope, the same all over
    hi = float(tr.t[-1]) if t_to is None else t_to
    values = []
    # each leg's touchdowns (the first of its soles to touch); a legless creature's contacts'
    soles = [tr.soles_of(i) for i in range(len(tr.leg_feet))] or [
        (c,) for c in range(len(tr.contact_names))
    ]
    for own in soles:
        starts, _ = runs(np.any(tr.contact[:, list(own)] != 0, axis=1))
        for k in starts.tolist():
            if k == 0 or not t_from <= tr.t[k] <= hi:
                continue
            c = next(i for i in own if tr.contact[k, i])
            q = [float(x) for x in tr.q[k - 1] / q_f]
            v = [float(x) for x in tr.v[k - 1] / v_f]
            velocity = dyn.contact_velocities(q, v)[c]
            values.append(math.sqrt(scale) * speed_along(velocity, normal))
    return stat(KEY, LABEL, values)


def speed_along(velocity: Sequence[float], normal: Sequence[float]) -> float:
    """The speed of ``velocity`` along the surface whose unit normal is ``normal``: its part
    tangent to it (on level ground, the horizontal speed)."""
    v, n = np.asarray(velocity, dtype=float), np.asarray(normal, dtype=float)
    return float(np.linalg.norm(v - np.dot(v, n) * n))
