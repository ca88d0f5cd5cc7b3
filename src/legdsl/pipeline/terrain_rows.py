"""The body against the terrain in ``legdsl metrics``: the least margin to each step and box.

The ground model pushes on contact points only, so a run can pass a trunk or a tail through
a box (``legdsl.sim.contact``). For a run whose ground has steps or boxes, this recomputes
the body poses of the samples in the window with the creature's generated dynamics (as the
apex clearance does, ``legdsl.pipeline.apex``) and measures each feature's least margin to
the creature's shapes (``legdsl.analysis.clearance``): negative when some body overlapped
it, by that depth. A run made with ``--scale L`` is measured as the scaled creature.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from legdsl.analysis.clearance import terrain_contacts
from legdsl.analysis.friction import LEVEL
from legdsl.analysis.recorded import model_if_readable
from legdsl.analysis.results import Summary
from legdsl.ir.model import Model
from legdsl.pipeline.apex import Kinematics
from legdsl.sim.contact import GroundContact
from legdsl.sim.trajectory import Trajectory


def ground_normal(run: Path) -> tuple[float, float, float]:
    """The unit normal of the run's ground, which the friction needed is measured against:
    a slope's, else (and when the creature's file is not found from here) level."""
    model = model_if_readable(run)
    return LEVEL if model is None else model_ground_normal(model)


def model_ground_normal(model: Model) -> tuple[float, float, float]:
    """The unit normal of ``model``'s ground: a slope's, else level."""
    if model.ground is None:
        return LEVEL
    return GroundContact(model.ground, (), model.planar).surface(0.0, 0.0)[1]


def terrain_rows(
    found: Kinematics, tr: Trajectory, t_from: float, t_to: float | None
) -> list[Summary]:
    """One row per step or box of the run's ground (none without them), measured with the
    run's creature ``found``."""
    model, dyn, q_f, scale = found
    terrain = model.ground.terrain if model.ground else ()
    if not any(t.kind in ("step", "box") for t in terrain):
        return []
    hi = float(tr.t[-1]) if t_to is None else t_to
    inside = np.flatnonzero((tr.t >= t_from) & (tr.t <= hi))
    poses = [dyn.body_poses([float(x) for x in tr.q[k] / q_f]) for k in inside]
    times = [float(x) for x in tr.t[inside]]
    found_rows = terrain_contacts(model.bodies, terrain, times, poses, model.planar)
    rows = []
    for c in found_rows:
        t = terrain[c.feature]
        where = (
            f"step at x = {scale * t.get('x'):g} m"
            if t.kind == "step"
            else f"box {scale * t.get('x0'):g}..{scale * t.get('x1'):g} m"
        )
        when = f", {c.body} at {c.t:g} s" if c.body else ""  # none: no sample in the window
        rows.append(
            Summary(
                f"terrain_margin_{c.feature}",
                f"least margin of the body to the {where}{when} (m)",
                scale * c.margin,
                float("nan"),
                len(c.overlapping),
                "min",
            )
        )
    return rows
