"""The kangaroo's jump (creatures/kangaroo.leg, controller `jump`) over a box 0.3 m tall and
deep, on a short run: docs/kangaroo.md has the 20 s runs at 10 m (docs/scripts/kangaroo_jump.py).

At 4 m/s with the box at 7 m the kangaroo takes off once, no point of its shapes meets the box
(legdsl.analysis.clearance, on the recorded poses), it lands beyond it, is back within 5% of
the command by the third stride after landing, and hops on to the end.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT

sys.path.insert(0, str(ROOT / "docs" / "scripts"))
import kangaroo_jump  # noqa: E402


@pytest.fixture(scope="module")
def jumped(generated: Path, tmp_path_factory: pytest.TempPathFactory):  # type: ignore[no-untyped-def]
    source = kangaroo_jump.box_file(tmp_path_factory.mktemp("box"), 7.0, 0.3, 0.3)
    model, dyn, run = kangaroo_jump.jump(source, 4.0, 6.5, generated)
    return model, dyn, run, kangaroo_jump.report(model, dyn, run, 4.0)


def test_the_kangaroo_clears_the_box_lands_and_hops_on(jumped) -> None:  # type: ignore[no-untyped-def]
    _, _, run, r = jumped
    assert run.status == "ok", run.message
    assert r["overlap_samples"] == 0 and r["margin_m"] > 0.03
    assert r["landed_t"] is not None and r["landed_t"] < 5.0
    assert r["first_stride_of_three_within_5pct"] is not None
    assert r["first_stride_of_three_within_5pct"] <= 3, r["strides_after_landing_m_s"]


def _flights(tr) -> list[tuple[float, float]]:  # type: ignore[no-untyped-def]
    """(duration, apex) of each flight of the toe that starts and ends in the run."""
    up = np.r_[False, tr.contact[:, tr.contact_names.index("toe")] == 0, False].astype(int)
    starts, ends = np.flatnonzero(np.diff(up) == 1), np.flatnonzero(np.diff(up) == -1)
    return [
        (float(tr.t[b - 1] - tr.t[a]), float(tr.com[a:b, 2].max()))
        for a, b in zip(starts, ends, strict=True)
        if a > 0 and b < len(tr.t)
    ]


def test_one_jump_and_hops_before_and_after(jumped) -> None:  # type: ignore[no-untyped-def]
    _, _, run, _ = jumped
    flights = _flights(run.trajectory)
    long = [f for f in flights if f[0] > 0.4]
    assert len(long) == 1  # one jump; every other flight is a hop's
    assert long[0][1] > 0.8 > max(h for d, h in flights if d <= 0.4 and d > 0.05)


def test_without_the_box_the_jump_controller_hops_like_hop(generated: Path) -> None:
    model, _, run = kangaroo_jump.jump(kangaroo_jump.KANGAROO, 4.0, 3.0, generated)
    assert run.status == "ok"
    assert max(d for d, _ in _flights(run.trajectory)) < 0.4


def test_the_animators_jump_at_a_time_on_flat_ground(generated: Path) -> None:
    _, _, run = kangaroo_jump.jump(kangaroo_jump.KANGAROO, 4.0, 6.0, generated, jump_time=4.0)
    assert run.status == "ok", run.message
    flights = _flights(run.trajectory)
    long = [d for d, _ in flights if d > 0.4]
    assert len(long) == 1  # once, however long the run
    starts = [e["t"] for e in run.events if e["kind"] == "state" and e["state"] == "FLIGHT"]
    takeoff = next(t for t in starts if t > 4.0)
    assert max(h for d, h in flights if d > 0.4) > 0.8
    assert takeoff < 4.6  # the first touchdown after 4 s was the take-off


def test_legdsl_metrics_reports_the_margin_to_the_box(
    jumped, generated: Path, tmp_path: Path
) -> None:  # type: ignore[no-untyped-def]
    from legdsl.pipeline.measure import measure_run
    from legdsl.pipeline.scaled import run_options
    from legdsl.pipeline.session import RunSession

    _, _, _, r = jumped
    source = kangaroo_jump.box_file(tmp_path / "box", 7.0, 0.3, 0.3)
    session = RunSession.from_file(source, generated=generated)
    run = session.run("jump", ["speed=4m/s"], options=run_options(session.model, duration=6.5))
    run.write(tmp_path / "run")
    metrics, _ = measure_run(tmp_path / "run", generated=generated)
    (row,) = [s for s in metrics.summaries if s.key.startswith("terrain_margin_")]
    assert row.value == pytest.approx(r["margin_m"], abs=1e-9)  # the same run, the same check
    assert row.n == 0 and "box 7..7.3 m" in row.label
