"""How well a run's centre of mass followed the path its controller was given."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from legdsl.analysis.results import jsonable
from legdsl.analysis.strides import EPS_T
from legdsl.figures import figure
from legdsl.sim.trajectory import Trajectory

if TYPE_CHECKING:
    from legdsl.ir.paths import PathSpec

PATH_FROM = 3.0  # s: the report's window starts here by default (after the start-up)


def path_report(
    tr: Trajectory, spec: PathSpec, t_from: float = PATH_FROM, t_to: float | None = None
) -> dict[str, Any]:
    """How well the centre of mass followed a path, from ``t_from``.

    The lateral deviation is the signed distance of the centre of mass from the
    path (positive to the left); its RMS, largest magnitude and mean are taken
    over the samples in the window. The progress is tracked from the run's
    first sample (so laps count from the start); the speed along the path is
    the progress made in the window over its duration.
    """
    from legdsl.sim.path_tracking import PathGeometry, track

    lateral, progress = track(
        spec, [float(x) for x in tr.com[:, 0]], [float(y) for y in tr.com[:, 1]]
    )
    lat = np.asarray(lateral)
    prog = np.asarray(progress)
    end = tr.t[-1] if t_to is None else t_to
    window = (tr.t >= t_from - EPS_T) & (tr.t <= end + EPS_T)
    geometry = PathGeometry(spec)
    length = geometry.length
    out: dict[str, Any] = {
        "path": spec.describe(),
        "closed": bool(geometry.closed),  # else "laps" is the fraction of the path covered
        "from": float(t_from),
        "to": float(end),
        "samples": int(window.sum()),
        "length": float(length),
        "progress": float(prog[-1] - prog[0]) if len(prog) else math.nan,
        "laps": float((prog[-1] - prog[0]) / length) if len(prog) and length > 0 else math.nan,
    }
    if window.sum() >= 2:
        w = lat[window]
        t = tr.t[window]
        out |= {
            "lateral_rms": float(np.sqrt(np.mean(w**2))),
            "lateral_max": float(np.max(np.abs(w))),
            "lateral_mean": float(np.mean(w)),
            "path_speed": float((prog[window][-1] - prog[window][0]) / (t[-1] - t[0])),
        }
    else:
        out |= dict.fromkeys(("lateral_rms", "lateral_max", "lateral_mean", "path_speed"), math.nan)
    return jsonable(out)


def path_rows(report: Mapping[str, Any]) -> list[tuple[str, str]]:
    """The report as (label, value) rows for ``legdsl run``'s summary and ``legdsl metrics``."""

    def num(key: str, unit: str) -> str:
        v = report.get(key)
        return "n/a" if v is None else f"{figure(v)}{unit}"

    window = f"from {report['from']:g} s"
    covered = "laps of" if report.get("closed", True) else "of its"  # open: the fraction covered
    return [
        ("path", str(report["path"])),
        (f"lateral deviation RMS ({window})", num("lateral_rms", " m")),
        (
            f"lateral deviation max / mean ({window})",
            f"{num('lateral_max', ' m')} / {num('lateral_mean', ' m')}",
        ),
        (
            "progress along the path",
            f"{num('progress', ' m')} ({num('laps', '')} {covered} {num('length', ' m')})",
        ),
        (f"speed along the path ({window})", num("path_speed", " m/s")),
    ]
