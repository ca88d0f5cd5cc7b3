"""The friction coefficient a contact needed, on a slope, is measured across and along the
tilted surface: a foot standing still on 30 deg needs tan(30 deg) = 0.577 (the world-frame
forces, all vertical, read 0, and a user who set friction from that would slide)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES

from legdsl.analysis.metrics import compute_metrics
from legdsl.pipeline.measure import measure_run
from legdsl.sim.trajectory import empty


def _standing_run(tmp_path: Path, terrain: str) -> Path:
    text = CREATURES.joinpath("hopper.leg").read_text()
    assert "    friction none\n  }" in text
    source = tmp_path / "hopper.leg"
    if terrain:
        text = text.replace("    friction none\n  }", f"    friction none\n    {terrain}\n  }}", 1)
    source.write_text(text)
    n = 101
    tr = empty(
        n, 3, 3, 1, 1, q_names=("x", "z", "pitch"), v_names=("x", "z", "pitch"),
        contact_names=("toe",), leg_names=("main",), leg_feet=(0,), total_mass=1.0, gravity=9.81,
    )  # fmt: skip
    tr.t[:] = np.linspace(0.0, 1.0, n)
    tr.q[:] = tr.v[:] = tr.com[:] = tr.com_vel[:] = tr.root_rpy[:] = 0.0
    tr.force[:] = 0.0
    for start in (10, 40, 70):  # three stances, each holding the body's weight, straight up
        tr.contact[start : start + 20, 0] = 1
        tr.force[start : start + 20, 0, 2] = 9.81
    out = tmp_path / "run"
    tr.save(out)
    (out / "run.json").write_text(json.dumps({"source": str(source), "creature": "hopper"}))
    return out


def test_a_foot_holding_still_on_a_slope_needed_its_tangent(tmp_path: Path) -> None:
    metrics, _ = measure_run(_standing_run(tmp_path, "terrain slope(angle = 30 deg)"))
    row = next(s for s in metrics.summaries if s.key == "friction_toe")
    assert row.value == pytest.approx(math.tan(math.radians(30)))


def test_on_level_ground_and_on_a_step_the_vertical_push_needs_none(tmp_path: Path) -> None:
    metrics, _ = measure_run(_standing_run(tmp_path, "terrain step(x = 2 m, height = 5 cm)"))
    assert next(s for s in metrics.summaries if s.key == "friction_toe").value == 0.0


def test_compute_metrics_takes_the_ground_normal(tmp_path: Path) -> None:
    from legdsl.sim.trajectory import Trajectory

    tr = Trajectory.load(_standing_run(tmp_path, ""))
    a = math.radians(-20)
    metrics = compute_metrics(tr, ground_normal=(-math.sin(a), 0.0, math.cos(a)))
    row = next(s for s in metrics.summaries if s.key == "friction_toe")
    assert row.value == pytest.approx(math.tan(math.radians(20)))


def test_the_api_measures_against_the_slope_as_legdsl_metrics(tmp_path: Path) -> None:
    """``run.metrics()`` measured the world's z and horizontal where ``legdsl metrics`` took
    the slope's surface."""
    import legdsl

    text = CREATURES.joinpath("hopper.leg").read_text()
    source = tmp_path / "hopper.leg"
    source.write_text(text.replace("    friction none\n  }",
                                   "    friction none\n    terrain slope(angle = 10 deg)\n  }", 1))  # fmt: skip
    run = legdsl.load(source, generated=tmp_path / "g").run(controller="hop", time=1.5)
    measured, _ = measure_run(run.save(tmp_path / "run"), generated=tmp_path / "g")
    along_slope = run.metrics().value("friction_toe")
    assert along_slope == measured.value("friction_toe")
    assert along_slope != compute_metrics(run.trajectory).value("friction_toe")  # world axes
