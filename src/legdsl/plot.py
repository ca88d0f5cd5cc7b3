"""``legdsl plot DIR``: a run drawn like Figure 6 of the paper.

Four panels against time: body height, body pitch, forward speed with its
command, and the joint angles of a leg; every stance phase of that leg is
bracketed by vertical dashed lines, as in the paper.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .trajectory import Trajectory

LINE_STYLES = ("-", "--", "-.", ":")


def stance_phases(tr: Trajectory, leg: int) -> list[tuple[float, float]]:
    """(touchdown, liftoff) times of a leg's foot; an open stance ends at the last sample."""
    touching = tr.contact[:, tr.leg_feet[leg]].astype(bool)
    phases = []
    start = None
    for i, now in enumerate(touching):
        if now and start is None:
            start = tr.t[i]
        elif not now and start is not None:
            phases.append((start, tr.t[i]))
            start = None
    if start is not None:
        phases.append((start, tr.t[-1]))
    return phases


def leg_coordinates(tr: Trajectory, joints: tuple[str, ...]) -> list[str]:
    """The coordinates of a leg's joints that are angles (gimbal parts included)."""
    names = []
    for name in tr.q_names:
        if any(name == j or name.startswith(j + "_") for j in joints):
            names.append(name)
    return names


def plot_run(
    run: Path,
    out: Path,
    leg_joints: tuple[str, ...] | None = None,
    t_from: float = 0.0,
    t_to: float | None = None,
) -> Path:
    """Draw the Figure-6 panels of a run into ``out`` (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    tr = Trajectory.load(run)
    end = tr.t[-1] if t_to is None else t_to
    window = (tr.t >= t_from) & (tr.t <= end)
    t = tr.t[window]
    fig, axes = plt.subplots(4, 1, figsize=(8, 9), sharex=True)
    height, pitch, speed, joints = axes

    height.plot(t, tr.com[window, 2], color="k")
    height.set_ylabel("body height (m)")
    pitch.plot(t, np.degrees(tr.root_rpy[window, 1]), color="k")
    pitch.set_ylabel("body pitch (deg)")

    heading = tr.root_rpy[window, 2]
    forward = tr.com_vel[window, 0] * np.cos(heading) + tr.com_vel[window, 1] * np.sin(heading)
    speed.plot(t, forward, color="k", label="forward speed")
    if np.isfinite(tr.speed_command[window]).any():
        speed.plot(t, tr.speed_command[window], color="0.5", linestyle="--", label="command")
        speed.legend(loc="lower right", fontsize=8)
    speed.set_ylabel("forward speed (m/s)")

    names = leg_coordinates(tr, leg_joints) if leg_joints else []
    for k, name in enumerate(names):
        column = tr.q_names.index(name)
        style = LINE_STYLES[k % len(LINE_STYLES)]
        joints.plot(t, np.degrees(tr.q[window, column]), color="k", linestyle=style, label=name)
    if names:
        joints.legend(loc="lower right", fontsize=8, ncol=len(names))
    joints.set_ylabel("leg joint angles (deg)")
    joints.set_xlabel("time (s)")

    if tr.leg_names:
        for start, stop in stance_phases(tr, 0):
            if stop < t_from or start > end:
                continue
            for ax in axes:
                ax.axvline(start, color="0.6", linestyle="--", linewidth=0.8)
                ax.axvline(stop, color="0.6", linestyle="--", linewidth=0.8)
    creature = run.name
    fig.suptitle(
        f"{creature}: stance phases of leg '{tr.leg_names[0]}' between dashed lines"
        if tr.leg_names
        else creature
    )
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=100)
    plt.close(fig)
    return out


def first_leg_joints(run: Path) -> tuple[str, ...] | None:
    """The joints of the run's first leg, read back from its creature's .leg file."""
    import json

    from .checker import check_model

    info = json.loads((run / "run.json").read_text())
    source = Path(info["source"])
    if not source.is_file():
        return None
    model = check_model(source, info.get("creature"))
    return model.legs[0].joints if model.legs else None
