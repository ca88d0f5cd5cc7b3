"""``Run.metrics()``: its arguments read as ``legdsl metrics`` reads its options, and the run
measured on the command's path (``legdsl.pipeline.measure.measure``), the rows measured on
the creature's geometry included: the run's kinematics are at hand, loaded with it."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

from legdsl.analysis.metrics import parse_groups, without_path_travel
from legdsl.analysis.path_report import followed_in, followed_reports, time_unit
from legdsl.analysis.results import GaitMetrics, MetricsError
from legdsl.analysis.series_units import series_unit
from legdsl.api.arguments import friction_edge_time, metrics_groups, min_stance_time, window_time
from legdsl.check.values import did_you_mean
from legdsl.ir.model import Model
from legdsl.lang.errors import UsageError
from legdsl.pipeline.apex import ROWS, Kinematics
from legdsl.pipeline.measure import measure
from legdsl.pipeline.scaled import q_factors
from legdsl.pipeline.terrain_rows import model_ground_normal
from legdsl.sim.trajectory import Trajectory


def run_metrics(
    model: Model,
    trajectory: Trajectory,
    info: Mapping[str, Any],
    dynamics: Callable[[], Any],
    start: object,
    end: object,
    leg: object,
    groups: Mapping[str, Sequence[str]] | Sequence[str],
    min_stance: float | str | None,
    friction_edge: float | str,
    joint: object = None,
    against: object = None,
) -> GaitMetrics:
    """The metrics of a run of ``model`` (``info`` its run.json; ``dynamics()`` its generated
    dynamics module) over ``[start, end]``, as ``legdsl metrics`` measures them, with the report
    of each path the run followed (``path_reports``); ``joint`` and ``against`` are ``--joint``
    and ``--against``, coordinates of ``model``."""
    t_from = window_time("start", start)
    t_to = None if end is None else window_time("end", end)
    texts, shortest = metrics_groups(groups), min_stance_time(min_stance)
    edge = friction_edge_time(friction_edge)
    if leg is not None and not isinstance(leg, str):
        raise UsageError(f"metrics(): leg= is the name of a leg, group or contact, not {leg!r}")
    try:
        given = parse_groups(texts)
    except MetricsError as e:
        raise UsageError(str(e)) from None
    slides = _joint_slides(model, trajectory, joint, against)
    welded = model.welded_root is not None  # goes nowhere: its travel rows n/a, as the command's
    metrics = measure(trajectory, _kinematics(model, info, dynamics), t_from=t_from, t_to=t_to,
                      leg=leg, groups=given, min_stance=shortest, edge=edge, joint=joint,
                      against=against, joint_slides=slides,
                      ground_normal=model_ground_normal(model), events=info.get("events"),
                      welded=welded, run_info=info)  # fmt: skip
    followed = followed_in(info, "the run's run.json")
    reports = [r for _, r in followed_reports(trajectory, followed, t_from or None, t_to,
                                              time_unit(info))]  # fmt: skip
    metrics.path_reports = [without_path_travel(r) for r in reports] if welded else reports
    return metrics


def _joint_slides(model: Model, trajectory: Trajectory, joint: object, against: object) -> bool:
    """``joint=`` and ``against=`` checked as ``legdsl metrics --joint --against`` checks them,
    in the words of the call: whether ``joint`` slides (its magnitude is then in metres)."""
    named = ", ".join(trajectory.q_names) or "none"
    for role, name in (("joint", joint), ("against", against)):
        if name is not None and not isinstance(name, str):
            raise UsageError(f"metrics(): {role}= is the name of a coordinate ({named}), "
                             f"not {name!r}")  # fmt: skip
        if name is not None and name not in trajectory.q_names:
            raise UsageError(f"metrics(): {role}={name!r}: no coordinate named so"
                             f"{did_you_mean(name, trajectory.q_names)} (coordinates: {named})")  # fmt: skip
    if joint is None:
        if against is not None:
            raise UsageError(f"metrics(): against={against!r} needs joint=: the correlation is "
                             "of the joint with it, e.g. joint='tail_base', against='hip'")  # fmt: skip
        return False
    unit = series_unit(model, f"q.{joint}")
    if unit == "":  # of the coordinates, only a quaternion's component is a pure number
        angles = [n for n in trajectory.q_names if series_unit(model, f"q.{n}")]
        raise UsageError(f"metrics(): joint={joint!r} is a component of the root's orientation "
                         f"quaternion, not an angle or a length; give a joint's coordinate "
                         f"({', '.join(angles)})")  # fmt: skip
    return unit == "m"


def _kinematics(
    model: Model, info: Mapping[str, Any], dynamics: Callable[[], Any]
) -> Kinematics | str:
    """The run's kinematics as ``legdsl metrics`` has them (a ``--scale L`` run measured as
    the scaled creature), or why not (a run that came through pickle, its module gone since)."""
    try:
        module = dynamics()
    except UsageError as gone:
        return f"{ROWS}: {gone}"
    scale = float(info.get("scale") or 1.0)
    return Kinematics(model, module, q_factors(model, scale), scale)
