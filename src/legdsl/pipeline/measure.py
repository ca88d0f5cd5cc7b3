"""``legdsl metrics``: the gait metrics and path reports of a run directory a session wrote."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from legdsl.analysis.metrics import compute_metrics, parse_groups, without_path_travel
from legdsl.analysis.pairs import PAIR_NAMES, group_hint
from legdsl.analysis.path_report import followed_reports, time_unit
from legdsl.analysis.plot import run_followed, samples_in_window
from legdsl.analysis.recorded import model_if_readable, one_run, recorded_model, run_source
from legdsl.analysis.results import (
    FRICTION_EDGE,
    WELDED,
    GaitMetrics,
    MetricsError,
    write_json,
)
from legdsl.analysis.segments import segment_report
from legdsl.analysis.series_units import series_unit
from legdsl.analysis.strides import debounced
from legdsl.analysis.table2 import MEASURE, step_legs, virtual_legs
from legdsl.check.source import check_model
from legdsl.ir.model import Model
from legdsl.lang.errors import UsageError
from legdsl.pipeline.apex import Kinematics, clearance_row, kinematics_or_why, with_clearance
from legdsl.pipeline.terrain_rows import ground_normal, terrain_rows
from legdsl.pipeline.touchdown import touchdown_speed_row
from legdsl.sim.trajectory import Trajectory, load_run_info


def measure_run(
    run: str | Path,
    t_from: float = 0.0,
    t_to: float | None = None,
    leg: str | None = None,
    groups: Sequence[str] = (),
    joint: str | None = None,
    against: str | None = None,
    generated: str | Path | None = None,
    table2: str | None = None,
    min_stance: float | None = None,
    friction_edge: float = FRICTION_EDGE,
) -> tuple[GaitMetrics, list[dict[str, Any]]]:
    """The metrics of ``run/trajectory.npz`` (also written to ``run/metrics.json``) and the
    lateral deviation from each path the run followed (from ``t_from``, else from 3 s scaled by
    the run's ``time_unit``). The
    foot clearance at the apex and the foot's speed over the ground at touchdown are measured
    with ``GENERATED/NAME/dynamics.py`` when it is there and fresh, GENERATED being
    ``generated``, else the folder run.json records, else generated/ (``legdsl.pipeline.apex``,
    ``legdsl.pipeline.touchdown``).

    ``groups`` are virtual legs, ``NAME=LEG,LEG``. With ``table2`` (a gait of Table 2 measured
    on virtual legs, such as "quadruped bound") and no ``groups``, the gait's pairs are found
    from the creature's hips (``legdsl.analysis.table2.virtual_legs``) and, without ``leg``,
    strides start at its reference pair's touchdowns. A request the run cannot answer (no or a
    damaged trajectory, an unknown leg, an empty window) raises ``UsageError``. ``min_stance``
    (s) is ``compute_metrics``'s: a shorter contact is no touchdown; ``friction_edge`` (s) its
    ``edge``, left out at each end of a stance for the interior friction row. A creature
    whose root is welded to the world (``Model.welded_root``, as ``legdsl run``'s summary decides
    it, from its .leg file) has its rows of travel and attitude, and its path reports, n/a.
    """
    run = Path(run)
    trajectory = Trajectory.load(run)  # a missing or damaged file is a UsageError
    one_run(run, trajectory)  # and so is a trajectory.npz of another run than run.json's
    if t_to is None or t_to >= t_from:  # else compute_metrics says the window is reversed
        samples_in_window(trajectory, run, t_from, t_to, "measure")
    try:
        given = parse_groups(groups)
        if table2 is not None and MEASURE.get(table2, {}).get("pairs"):
            if given:  # pairs by hand replace the ones found: strides start at the gait's
                _rows_can_read(table2, given)
                pair = MEASURE[table2].get("reference")  # reference pair, else the first
                first: str | None = pair if pair in given else next(iter(given))
            elif MEASURE[table2]["pairs"] == "steps":  # every leg, named in the trajectory
                given, first = step_legs(table2, trajectory.leg_names)
            else:
                given, first = virtual_legs(table2, run_model(run, table2))
            leg = leg if leg is not None else first
    except MetricsError as e:
        raise UsageError(str(e)) from None
    model = model_if_readable(run)  # None: a trajectory whose creature is not at hand
    welded = model is not None and model.welded_root is not None
    metrics = measure(
        trajectory,
        kinematics_or_why(run, trajectory, None if generated is None else Path(generated)),
        t_from=t_from,
        t_to=t_to,
        leg=leg,
        groups=given,
        joint=joint,
        against=against,
        joint_slides=joint is not None and _slides(run, joint),
        min_stance=min_stance,
        edge=friction_edge,
        ground_normal=ground_normal(run),
        events=_events(run),
        welded=welded,
        run_info=load_run_info(run) if (run / "run.json").is_file() else None,  # how it ended
    )
    try:
        write_json(metrics, run / "metrics.json")
    except OSError as e:  # the measurement stands: it was refused, with nothing printed
        metrics.unwritten = (f"{run / 'metrics.json'} not written ({e.strerror or e}): the "
                             "metrics are only printed")  # fmt: skip
    followed, unit = run_followed(run), _time_unit(run)
    reports = [r for _, r in followed_reports(trajectory, followed, t_from or None, t_to, unit)]
    reports = [without_path_travel(r) for r in reports] if welded else reports
    metrics.path_reports = reports
    return metrics, reports


def measure(trajectory: Trajectory, kinematics: Kinematics | str, **options: Any) -> GaitMetrics:
    """The metrics of a trajectory, ``compute_metrics(trajectory, **options)`` (a request the
    run cannot answer raises ``UsageError``), with the rows measured on the creature's geometry
    when its ``kinematics`` are at hand, else a note (``unmeasured``) saying why they are left
    out and how to have them. ``legdsl metrics`` and ``Run.metrics()`` both measure here."""
    try:
        metrics = compute_metrics(trajectory, **options)
    except MetricsError as e:
        raise UsageError(str(e)) from None
    if isinstance(kinematics, str):
        metrics.unmeasured = kinematics
        return metrics
    t_from, t_to = metrics.t_from, metrics.t_to
    row = clearance_row(kinematics, trajectory, metrics.flights)
    metrics.summaries = with_clearance(metrics.summaries, row)
    touched = debounced(trajectory, options.get("min_stance"))  # a scuff is no touchdown here
    speed = touchdown_speed_row(kinematics, touched, t_from, t_to)
    keys = [s.key for s in metrics.summaries]  # the speed before the friction rows
    at = next((i for i, k in enumerate(keys) if k.startswith("friction_")), len(keys))
    metrics.summaries.insert(at, speed)
    metrics.summaries += terrain_rows(kinematics, trajectory, t_from, t_to)
    return metrics


def _events(run: Path) -> list[dict[str, Any]]:
    """run.json's events (none for a trajectory without it: the samples time everything)."""
    return load_run_info(run).get("events", []) if (run / "run.json").is_file() else []


def _time_unit(run: Path) -> float:
    """The run's ``time_unit`` (1 for a trajectory without run.json)."""
    return time_unit(load_run_info(run)) if (run / "run.json").is_file() else 1.0


def _rows_can_read(table2: str, given: dict[str, list[str]]) -> None:
    """Pairs given by hand for a gait whose rows read pairs by name (the bound's front and
    rear) must have those names: else the rows came out n/a without a word."""
    pairing = MEASURE[table2]["pairs"]
    missing = [n for n in PAIR_NAMES.get(pairing, ()) if n not in given]
    if missing:
        raise UsageError(
            f"--table2 {table2!r} measures groups named {' and '.join(PAIR_NAMES[pairing])}, "
            f"and no --group is named {' or '.join(missing)}: give {group_hint(pairing)}"
        )


def run_segments(run: str | Path) -> list[dict[str, Any]]:
    """The controller segments of a run that switched controllers (none for other runs),
    each measured (``legdsl.analysis.segments``); their speeds n/a for a creature whose root
    is welded to the world."""
    run = Path(run)
    if not (run / "run.json").is_file():
        return []
    segments = load_run_info(run).get("segments")
    if not isinstance(segments, list) or not all(isinstance(s, dict) for s in segments):
        return []
    report = segment_report(Trajectory.load(run), segments, _time_unit(run))
    model = model_if_readable(run)
    if model is None or model.welded_root is None:
        return report
    gone = {"speed": None, "error_percent": None, "why": WELDED}  # it goes nowhere
    return [r | gone for r in report]


def _slides(run: Path, joint: str) -> bool:
    """Whether coordinate ``joint`` of the run's creature slides (its magnitude is then a
    length), from the creature's ``.leg`` file; False (an angle) when that is not at hand. A
    component of a 3D root's quaternion has no magnitude to report."""
    info = load_run_info(run)
    if run_source(run, info) is None:
        return False
    _, model = recorded_model(run, info)
    unit = series_unit(model, f"q.{joint}")
    if unit == "":  # of the coordinates, only a quaternion's component is a pure number
        named = [n for n in model.q_names if series_unit(model, f"q.{n}")]
        raise UsageError(
            f"--joint {joint}: a component of the root's orientation quaternion, not an angle "
            f"or a length; give a joint's coordinate ({', '.join(named)})"
        )
    return unit == "m"


def run_model(run: Path, why: str) -> Model:
    """The creature a run directory's run.json names, checked from its .leg file."""
    info = load_run_info(run)
    named = Path(str(info.get("source", "")))
    source = next((c for c in (named, run / named, run / named.name) if c.is_file()), None)
    if source is None:
        raise UsageError(
            f"{why}: its pairs of legs are found from the creature, but {run}/run.json names "
            f"the file {str(named)!r}, which is not there; give the pairs with "
            f"{group_hint(MEASURE.get(why, {}).get('pairs', ''))}"
        )
    return check_model(source, info.get("creature"))
