"""``legdsl metrics``: the gait metrics and path reports of a run directory a session wrote."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from legdsl.analysis.metrics import compute_metrics, parse_groups
from legdsl.analysis.path_report import PATH_FROM, path_report
from legdsl.analysis.plot import run_paths
from legdsl.analysis.results import GaitMetrics, MetricsError, write_json
from legdsl.lang.errors import UsageError
from legdsl.pipeline.apex import clearance_row, with_clearance
from legdsl.pipeline.terrain_rows import terrain_rows
from legdsl.pipeline.touchdown import touchdown_speed_row
from legdsl.sim.trajectory import Trajectory


def measure_run(
    run: str | Path,
    t_from: float = 0.0,
    t_to: float | None = None,
    leg: str | None = None,
    groups: Sequence[str] = (),
    joint: str | None = None,
    against: str | None = None,
    generated: str | Path = "generated",
) -> tuple[GaitMetrics, list[dict[str, Any]]]:
    """The metrics of ``run/trajectory.npz`` (also written to ``run/metrics.json``) and the
    lateral deviation from each path the run followed (from ``t_from``, else from 3 s). The
    foot clearance at the apex and the foot's speed over the ground at touchdown are measured
    with ``generated/NAME/dynamics.py`` when it is there and fresh (``legdsl.pipeline.apex``,
    ``legdsl.pipeline.touchdown``).

    ``groups`` are virtual legs, ``NAME=LEG,LEG``. A request the run cannot answer (no or a
    damaged trajectory, an unknown leg, an empty window) raises ``UsageError``.
    """
    run = Path(run)
    trajectory = Trajectory.load(run)  # a missing or damaged file is a UsageError
    try:
        metrics = compute_metrics(
            trajectory,
            t_from=t_from,
            t_to=t_to,
            leg=leg,
            groups=parse_groups(groups),
            joint=joint,
            against=against,
        )
    except MetricsError as e:
        raise UsageError(str(e)) from None
    row = clearance_row(run, trajectory, metrics.flights, Path(generated))
    metrics.summaries = with_clearance(metrics.summaries, row)
    speed = touchdown_speed_row(run, trajectory, t_from, t_to, Path(generated))
    if speed is not None:  # before the friction rows
        keys = [s.key for s in metrics.summaries]
        at = next((i for i, k in enumerate(keys) if k.startswith("friction_")), len(keys))
        metrics.summaries.insert(at, speed)
    metrics.summaries += terrain_rows(run, trajectory, t_from, t_to, Path(generated))
    try:
        write_json(metrics, run / "metrics.json")
    except OSError as e:
        raise UsageError(f"cannot write {run / 'metrics.json'}: {e.strerror or e}") from None
    start = t_from if t_from > 0 else PATH_FROM
    reports = [path_report(trajectory, spec, start, t_to) for spec in run_paths(run)]
    return metrics, reports
