"""How well a run's centre of mass followed the path its controller was given."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from legdsl.analysis.results import jsonable
from legdsl.analysis.strides import EPS_T
from legdsl.figures import figure
from legdsl.lang.errors import UsageError
from legdsl.sim.trajectory import Trajectory

if TYPE_CHECKING:
    from legdsl.ir.paths import PathSpec
    from legdsl.sim.path_tracking import PathGeometry

PATH_FROM = 3.0  # s: the report's window starts here by default (after the start-up)


def time_unit(info: Mapping[str, Any]) -> float:
    """The natural time of a run's creature over a 0.81 m one's (run.json's ``time_unit``:
    sqrt(standing height / 0.81 m), times sqrt(L) for a ``--scale L`` run; 1 for a run
    recorded without it), by which the reports' waits after a start or a takeover scale."""
    unit = info.get("time_unit", 1.0)
    if isinstance(unit, bool) or not isinstance(unit, int | float) or not 0 < unit < math.inf:
        raise UsageError(f"run.json: 'time_unit' is not a positive number ({str(unit)[:20]}); "
                         "run the creature again")  # fmt: skip
    return float(unit)


def settle_time(seconds: float, unit: float) -> float:
    """``seconds`` written for a 0.81 m creature, for one whose time ``unit`` is given (Table 1:
    times by sqrt(L)), to two figures: a wait to settle is no finer, and the shipped biped
    (0.83 m) and hopper (0.80 m) wait 3 s as the quadruped does."""
    return float(f"{seconds * unit:.2g}")


# A path and the spans of the run (from, to) its controllers followed it in: None when the
# whole run did (a run that changed to a controller following another path, or none, has spans)
Followed = tuple["PathSpec", "list[tuple[float, float]] | None"]


def path_report(
    tr: Trajectory,
    spec: PathSpec,
    t_from: float = PATH_FROM,
    t_to: float | None = None,
    track_from: float = -math.inf,
    track_to: float = math.inf,
) -> dict[str, Any]:
    """How well the centre of mass followed a path, from ``t_from``.

    The lateral deviation is the signed distance of the centre of mass from the
    path (positive to the left); its RMS, largest magnitude and mean are taken
    over the samples in the window. The progress is tracked from the run's
    first sample (so laps count from the start; from ``track_from`` to ``track_to`` for a
    path a controller took over with, as its tracker did); the speed along the path is
    the progress made in the window over its duration. Past an open path's end the runner
    goes on along its last side (docs/biped.md), and the lateral deviation is measured from
    that side's line: so is the speed, the way on along that line counting as progress
    (``_beyond_ends``), where the tracker's progress stops at the end. ``past_end`` is how
    far on the last sample is (negative: back before the start, along the first side).
    """
    from legdsl.sim.path_tracking import PathGeometry, track

    tracked = (tr.t >= track_from - EPS_T) & (tr.t <= track_to + EPS_T)
    times = tr.t[tracked]
    lateral, progress = track(
        spec, [float(x) for x in tr.com[tracked, 0]], [float(y) for y in tr.com[tracked, 1]]
    )
    lat = np.asarray(lateral)
    prog = np.asarray(progress)
    end = tr.t[-1] if t_to is None else t_to
    window = (times >= t_from - EPS_T) & (times <= end + EPS_T)
    geometry = PathGeometry(spec)
    length = geometry.length
    beyond = _beyond_ends(geometry, tr.com[tracked, :2], prog)
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
    if math.isfinite(track_from):  # followed from a controller's takeover, not the run's start
        out["followed_from"] = float(track_from)
    if len(times) and end < times[-1] - EPS_T:  # a window asked to end before the run does
        out["to_before_end"] = True
    if not geometry.closed:
        out["past_end"] = float(beyond[-1]) if len(beyond) else 0.0
    if window.sum() >= 2:
        w = lat[window]
        t = times[window]
        on = prog[window] + beyond[window]  # along the path, and on along its end sides' lines
        out |= {
            "lateral_rms": float(np.sqrt(np.mean(w**2))),
            "lateral_max": float(np.max(np.abs(w))),
            "lateral_mean": float(np.mean(w)),
            "path_speed": float((on[-1] - on[0]) / (t[-1] - t[0])),
        }
        if np.any(beyond[window] > 0):
            out["speed_past_end"] = True
        if np.any(beyond[window] < 0):
            out["speed_before_start"] = True
    else:
        out |= dict.fromkeys(("lateral_rms", "lateral_max", "lateral_mean", "path_speed"), math.nan)
    return jsonable(out)


# m: a tracked progress this near an open path's end (or its start) is there: the tracker sums
# its steps along the path, so its progress at the end is the length to rounding only
AT_END = 1e-6


def _beyond_ends(geometry: PathGeometry, xy: np.ndarray, prog: np.ndarray) -> np.ndarray:
    """How far each point is on past an open path's end along its last side's line (where its
    tracked progress is at the end), or back before its start along its first side's
    (negative, where it is at the start); 0 elsewhere, and all along a closed path. The
    tracker's nearest point stays at the end, and the lateral deviation there is the
    distance from that line (``PathGeometry.project``): this is the way along it."""
    beyond = np.zeros(len(prog))
    v = geometry.vertices
    if geometry.closed or len(v) < 2 or not len(prog):
        return beyond
    for (ax, ay), (bx, by), at, sign in (
        (v[-2], v[-1], prog >= geometry.length - AT_END, 1.0),
        (v[1], v[0], prog <= AT_END, -1.0),
    ):
        side = math.hypot(bx - ax, by - ay)
        along = ((xy[:, 0] - bx) * (bx - ax) + (xy[:, 1] - by) * (by - ay)) / side
        beyond = np.where(at & (along > 0), sign * along, beyond)
    return beyond


def followed_reports(
    tr: Trajectory,
    followed: Sequence[Followed],
    t_from: float | None,
    t_to: float | None,
    unit: float = 1.0,
) -> list[tuple[PathSpec, dict[str, Any]]]:
    """The reports of every path a run followed: one over the run (from ``t_from``, else from
    ``PATH_FROM``) for a path followed throughout, else one per span it was followed in
    (from ``PATH_FROM`` after the controller took over, or ``t_from`` within the span), its
    progress from the takeover: a path a later controller no longer follows is not measured
    against what the creature did after, nor one it took over with against what it did before.
    ``PATH_FROM`` is for a 0.81 m creature: ``unit`` (``time_unit``) scales it to the run's."""
    after = settle_time(PATH_FROM, unit)
    reports = []
    for spec, spans in followed:
        if spans is None:
            start = after if t_from is None else t_from
            reports.append((spec, path_report(tr, spec, start, t_to)))
            continue
        for start, end in spans:
            lo = min(start + after, end) if t_from is None else max(t_from, start)
            hi = end if t_to is None else min(t_to, end)
            if lo <= hi:  # a span outside the asked window has nothing to say
                reports.append((spec, path_report(tr, spec, lo, hi, start, end)))
    return reports


def path_rows(report: Mapping[str, Any]) -> list[tuple[str, str]]:
    """The report as (label, value) rows for ``legdsl run``'s summary and ``legdsl metrics``."""

    def num(key: str, unit: str) -> str:
        v = report.get(key)
        return "n/a" if v is None else f"{figure(v)}{unit}"

    window = window_label(report)
    covered = "laps of" if report.get("closed", True) else "of its"  # open: the fraction covered
    progress = f"{num('progress', ' m')} ({num('laps', '')} {covered} {num('length', ' m')})"
    past = report.get("past_end") or 0.0  # beyond an open path's end (or before its start)
    if past > 0:
        progress += f", then {figure(past)} m on past its end along its last side"
    elif past < 0:
        progress += f", and {figure(-past)} m back before its start along its first side"
    speed = f"speed along the path ({window}"
    if report.get("speed_past_end"):
        speed += "; on past its end"
    if report.get("speed_before_start"):
        speed += "; from before its start"
    speed += ")"
    return [
        ("path", str(report["path"])),
        (f"lateral deviation RMS ({window})", num("lateral_rms", " m")),
        (
            f"lateral deviation max / mean ({window})",
            f"{num('lateral_max', ' m')} / {num('lateral_mean', ' m')}",
        ),
        ("progress along the path", progress),
        (speed, num("path_speed", " m/s")),
    ]


def window_label(report: Mapping[str, Any]) -> str:
    """The report's window as its rows and the top view's title say it: "from 3 s", and "to
    5 s" where it ends before the run does (``--to``, or a later controller took over)."""
    window = f"from {report['from']:g} s"
    if "followed_from" in report or report.get("to_before_end"):
        window += f" to {report['to']:g} s"
    return window
