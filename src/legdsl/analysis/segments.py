"""The controller segments of a run that changed controllers (``legdsl run --switch``).

For each segment (from its switch to the next, as run.json's ``segments`` give them) the
report measures the forward speed (along the heading, the centre of mass's) averaged over
the samples from ``SETTLE`` after the switch to the segment's end, beside the commanded speed
averaged over the same samples, and their relative difference; a window shorter than
``SHORTEST`` (a stride or two) is too short to measure. Both are for a creature standing
0.81 m, and follow the run's size (``path_report.time_unit``). ``legdsl metrics`` prints it for a
switched run; ``--from``/``--to`` measure any one part of it in full.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from legdsl.analysis.averages import finite_mean
from legdsl.analysis.path_report import settle_time
from legdsl.analysis.strides import EPS_T
from legdsl.figures import figure
from legdsl.sim.trajectory import Trajectory

SETTLE = 3.0  # s after a switch (or the start) before its speed is measured
SHORTEST = 1.0  # s: the least window measured (60 ms of a 0.77 s stride gave a -12% "error")


def segment_report(
    tr: Trajectory, segments: Sequence[dict[str, Any]], unit: float = 1.0
) -> list[dict[str, Any]]:
    """One entry per segment: controller, from, to, the window measured, the mean forward
    speed and command in it (m/s, None where there is nothing to measure) and the error (%).
    ``SETTLE`` and ``SHORTEST`` are for a 0.81 m creature: ``unit`` (the run's
    ``time_unit``) scales them to its size, as the handover's waits scale (a quadruped scaled
    by 4 still ramped up 3 s after a takeover, and at 1/4 every segment was too short); each
    entry says them as ``settle`` and ``shortest``."""
    settle, shortest = settle_time(SETTLE, unit), settle_time(SHORTEST, unit)
    yaw = tr.root_rpy[:, 2]
    forward = tr.com_vel[:, 0] * np.cos(yaw) + tr.com_vel[:, 1] * np.sin(yaw)
    end = float(tr.t[-1]) if len(tr) else 0.0
    out = []
    for seg in segments:
        t0 = float(seg.get("from", 0.0))
        t1 = min(float(seg.get("to", end)), end)
        window = (tr.t >= t0 + settle - EPS_T) & (tr.t < t1 - EPS_T)
        if t1 - (t0 + settle) < shortest - EPS_T:
            window[:] = False
        speed = float(np.mean(forward[window])) if window.any() else math.nan
        cmd = tr.speed_command[window]
        command = finite_mean(cmd)  # of any size: 1e308 m/s overflowed numpy's mean
        error = 100 * (speed / command - 1) if command and math.isfinite(speed) else math.nan
        out.append(
            {
                "controller": seg.get("controller"),
                "from": t0,
                "to": t1,
                "measured_from": t0 + settle,
                "settle": settle,
                "shortest": shortest,
                "speed": speed if math.isfinite(speed) else None,
                "command": command if math.isfinite(command) else None,
                "error_percent": error if math.isfinite(error) else None,
            }
        )
    return out


def segment_table(report: Sequence[dict[str, Any]]) -> str:
    """The report as text, one line per segment."""
    settle = report[0]["settle"] if report else SETTLE
    shortest = report[0]["shortest"] if report else SHORTEST
    lines = [
        f"controller segments (speed from {settle:g} s after each switch to the next, "
        f"where that is {shortest:g} s or more):"
    ]
    for r in report:
        where = f"  {r['controller']:<14} {r['from']:>7.2f} to {r['to']:>7.2f} s"
        if r.get("why"):  # a creature that goes nowhere (its root welded to the world)
            lines.append(f"{where}  speed n/a ({r['why']})")
            continue
        if r["speed"] is None:
            lines.append(f"{where}  too short to measure")
            continue
        cmd = "" if r["command"] is None else f", command {figure(r['command'])} m/s"
        err = "" if r["error_percent"] is None else f" ({r['error_percent']:+.1f}%)"
        lines.append(
            f"{where}  speed {figure(r['speed'])} m/s{cmd}{err}, measured from "
            f"{r['measured_from']:.2f} s"
        )
    return "\n".join(lines) + "\n"
