"""The unit of each series a run records: what a plot's axis says (``Run.unit``), and
whether a coordinate's magnitude is a length (``legdsl metrics --joint``).

Every series is in SI units; which one a coordinate's is depends on its joint (a hinge's in
rad, a slide's in m), which the run's arrays do not say, so it is read from the creature.
"""

from __future__ import annotations

from legdsl.ir.model import Model

# series by their first part, and the few named whole
UNITS = {
    "t": "s", "com": "m", "com_vel": "m/s", "contact": "", "force": "N", "leg_length": "m",
    "state": "", "speed_command": "m/s", "energy": "J", "work_positive": "J",
    "work_negative": "J",
}  # fmt: skip
ROOT = {"x": "m", "y": "m", "z": "m", "roll": "rad", "pitch": "rad", "yaw": "rad"}
FREE_3D = {"x": "m", "y": "m", "z": "m", "qw": "", "qx": "", "qy": "", "qz": "",
           "vx": "m/s", "vy": "m/s", "vz": "m/s", "wx": "rad/s", "wy": "rad/s", "wz": "rad/s"}  # fmt: skip


def series_unit(model: Model, name: str) -> str | None:
    """The SI unit of series ``name`` of a run of ``model`` ('' for a pure number, a
    quaternion's component or a 0/1 contact); None for a name that is no series of it."""
    kind, _, rest = name.partition(".")
    if kind in ("q", "v"):
        motion = {d.name: d.motion for d in model.dofs}
        if rest in motion:
            unit = "m" if motion[rest] == "slide" else "rad"
            return unit if kind == "q" else f"{unit}/s"
        free = model.joints and model.joints[0].is_free_3d
        names = model.q_names if kind == "q" else model.v_names
        return FREE_3D.get(rest) if free and rest in names else None
    if kind == "root":
        return ROOT.get(rest)
    return UNITS.get(kind)
