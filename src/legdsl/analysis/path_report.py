"""How well a run's centre of mass followed the path its controller was given."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from legdsl.analysis.path_rows import shown_path, window_label
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


def followed_in(info: Mapping[str, Any], where: str) -> list[Followed]:
    """The paths a run's ``info`` (its run.json, ``where``) says it followed, each with the
    spans of the run it followed it in (``followed``: a run that changed to a controller with
    another path), None for the whole run; none for a run recorded without them."""
    from legdsl.ir.paths import PathSpec

    entries = info.get("paths") or []
    try:
        return [
            (
                PathSpec.from_json(e),
                [(float(a), float(b)) for a, b in e.get("followed") or []] or None,
            )
            for e in entries
        ]
    except (KeyError, TypeError, ValueError, AttributeError) as e:
        raise UsageError(f"{where}: a path in it is damaged ({e!r}); run again") from None


def path_report(
    tr: Trajectory,
    spec: PathSpec,
    t_from: float = PATH_FROM,
    t_to: float | None = None,
    track_from: float = -math.inf,
    track_to: float = math.inf,
    progress_from: float | None = None,
    unit: float = 1.0,
) -> dict[str, Any]:
    """How well the centre of mass followed a path over the window ``t_from`` to ``t_to``.

    The lateral deviation is the signed distance of the centre of mass from the
    path (positive to the left); its RMS, largest magnitude and mean are taken
    over the samples in the window. The nearest point is tracked from the run's first sample
    (from ``track_from`` to ``track_to`` for a path a controller took over with, as its
    tracker did); the progress and laps are how far it moved along the path from
    ``progress_from`` (default: where the tracking starts; ``legdsl metrics --from`` gives the
    window's start) to the window's end. The speed along the path is the mean over the window
    of the centre of mass's horizontal velocity along the path's tangent at its nearest point
    (each step of the centre of mass projected on that tangent, summed, over the window's
    duration): never more than its horizontal speed, where the nearest point's own pace is
    not (it sweeps round a circle's centre, and across a corner cut inside). Past an open
    path's end the runner goes on along its last side (docs/biped.md), and the lateral
    deviation and the tangent are that side's line's (``_beyond_ends``); ``past_end`` is how
    far on it is at the window's end (negative: back before the start, along the first side).
    ``size`` is the path's spread (``path_size``) and ``note`` says when the centre of mass
    kept further off the path than ``off_path_limit`` allows (``unit``: the run's
    ``time_unit``), its progress then the nearest point's, not a way it ran.
    """
    from legdsl.sim.path_tracking import PathGeometry, PathTracker

    tracked = (tr.t >= track_from - EPS_T) & (tr.t <= track_to + EPS_T)
    times = tr.t[tracked]
    xy = np.asarray(tr.com[tracked, :2], dtype=float)
    tracker = PathTracker(spec)
    lateral, progress, heading = [], [], []
    for x, y in xy:
        v = tracker.update(float(x), float(y))
        lateral.append(v["lateral"])
        progress.append(v["progress"])
        heading.append(v["heading"])
    lat, prog, head = np.asarray(lateral), np.asarray(progress), np.asarray(heading)
    end = tr.t[-1] if t_to is None else t_to
    window = (times >= t_from - EPS_T) & (times <= end + EPS_T)
    geometry = PathGeometry(spec)
    length = geometry.length
    beyond = _beyond_ends(geometry, xy, prog)
    counted = times <= end + EPS_T
    if progress_from is not None:
        counted &= times >= progress_from - EPS_T
    first, last = int(np.argmax(counted)), len(counted) - 1 - int(np.argmax(counted[::-1]))
    made = float(prog[last] - prog[first]) if counted.any() else math.nan
    since = track_from if math.isfinite(track_from) else times[0] if len(times) else t_from
    size = path_size(geometry)
    out: dict[str, Any] = {
        "path": spec.describe(),
        "closed": bool(geometry.closed),  # else "laps" is the fraction of the path covered
        "from": float(t_from),
        "to": float(end),
        "samples": int(window.sum()),
        "length": float(length),
        "progress_from": float(progress_from if progress_from is not None else since),
        "progress": made,
        "laps": made / length if length > 0 else math.nan,
        "size": size,
    }
    if math.isfinite(track_from):  # followed from a controller's takeover, not the run's start
        out["followed_from"] = float(track_from)
    if len(times) and end < times[-1] - EPS_T:  # a window asked to end before the run does
        out["to_before_end"] = True
    if not geometry.closed:
        out["past_end"] = float(beyond[last]) if counted.any() else 0.0
    if window.sum() >= 2:
        w = lat[window]
        t = times[window]
        steps = np.diff(xy[window], axis=0)
        tangent = np.column_stack([np.cos(head[window]), np.sin(head[window])])
        along = (tangent[1:] + tangent[:-1]) / 2  # the tangent over a step: its ends' mean
        out |= {
            "lateral_rms": float(np.sqrt(np.mean(w**2))),
            "lateral_max": float(np.max(np.abs(w))),
            "lateral_mean": float(np.mean(w)),
            "path_speed": float(np.sum(steps * along) / (t[-1] - t[0])),
        }
        if np.any(beyond[window] > 0):
            out["speed_past_end"] = True
        if np.any(beyond[window] < 0):
            out["speed_before_start"] = True
        out["note"] = off_path_note(out, unit)
    else:
        out |= dict.fromkeys(("lateral_rms", "lateral_max", "lateral_mean", "path_speed"), math.nan)
    return jsonable(out)


PATH_MARGIN = 1.0  # m: a path followed this far off, RMS, is missed (shipped runs: 0.01 to 0.4 m)
SIZE_SHARE = 0.5  # ... and so is one followed further off than half its spread ("half")


def path_size(geometry: PathGeometry) -> float | None:
    """A path's spread: the RMS distance of its points (all along it, evenly by arclength) from
    their centroid; a circle's radius, a square's 0.58 of its side, a 2 m zigzag's 0.68 m.
    None for a straight path (one side, or sides running on along one line), which any
    deviation can follow: only ``PATH_MARGIN`` holds for it."""
    if geometry.spec.shape == "circle":
        return float(geometry.spec.radius)
    v = np.asarray(geometry.vertices, dtype=float)
    if len(v) < 2:
        return None
    a, b = v[:-1], v[1:]
    sides = np.hypot(*(b - a).T)
    d = (b - a) / sides[:, None]
    if np.all(np.abs(d[:, 0] * d[0, 1] - d[:, 1] * d[0, 0]) < 1e-9) and np.all(d @ d[0] > 0):
        return None  # every side along the first, the same way: a straight line
    weight = sides / sides.sum()
    mid = (a + b) / 2
    centre = weight @ mid
    spread = weight @ (np.sum((mid - centre) ** 2, axis=1) + sides**2 / 12)
    return float(math.sqrt(spread))


def off_path_limit(report: Mapping[str, Any], unit: float = 1.0) -> tuple[float, str]:
    """The lateral deviation RMS past which a path is missed, and the limit as words:
    ``PATH_MARGIN`` for a 0.81 m creature (a length: times ``unit`` squared, Table 1), or
    ``SIZE_SHARE`` of the path's spread where that is less (a 5 cm circle, hairpins 0.3 m
    apart: a runner that far off is as near another part of the path, or the far side)."""
    margin = PATH_MARGIN * unit**2
    size = report.get("size")
    if size is not None and SIZE_SHARE * size < margin:
        return SIZE_SHARE * size, (
            f"half the path's spread ({figure(size)} m: the RMS distance of its points from "
            "their centroid)"
        )
    return margin, f"{margin:.3g} m"


def off_path_note(report: Mapping[str, Any], unit: float = 1.0) -> str | None:
    """What the report says of a path its centre of mass kept further off than
    ``off_path_limit``, else None."""
    rms, most = report.get("lateral_rms"), report.get("lateral_max")
    if rms is None or not math.isfinite(rms):
        return None
    limit, said = off_path_limit(report, unit)
    if rms <= limit:
        return None
    return (
        f"the centre of mass kept {figure(rms)} m off the path {shown_path(str(report['path']))} (RMS "
        f"{window_label(report)}, {figure(most or rms)} m at most), more than {said}: the "
        "controller did not follow this path, and its progress and laps are those of the "
        "path's point nearest the centre of mass, not a way it ran along the path"
    )


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
    The progress counts from the start (the takeover) unless ``t_from`` is given, then from
    it: every figure is then the window's. ``PATH_FROM`` is for a 0.81 m creature: ``unit``
    (``time_unit``) scales it to the run's, and the off-path note's ``PATH_MARGIN``."""
    after = settle_time(PATH_FROM, unit)
    reports = []
    for spec, spans in followed:
        if spans is None:
            start = after if t_from is None else t_from
            report = path_report(tr, spec, start, t_to, progress_from=t_from, unit=unit)
            reports.append((spec, report))
            continue
        for start, end in spans:
            lo = min(start + after, end) if t_from is None else max(t_from, start)
            hi = end if t_to is None else min(t_to, end)
            since = None if t_from is None else lo  # the progress: from the takeover, or --from
            if lo <= hi:  # a span outside the asked window has nothing to say
                reports.append((spec, path_report(tr, spec, lo, hi, start, end, since, unit)))
    return reports
