"""The friction window (``legdsl metrics --friction-edge``, ``run.metrics(friction_edge=)``):
the time left out at each end of a stance for the interior friction row, the paper's 10 ms
by default, and a creature's own (a small creature's stances are short: docs/scaling.md)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from legdsl.analysis.metrics import compute_metrics
from legdsl.analysis.results import GaitMetrics, MetricsError
from legdsl.cli import main
from legdsl.sim.trajectory import Trajectory, empty

DT = 0.001


def slipping_edges_run(n: int = 2001) -> Trajectory:
    """One planar leg on the ground for 100 ms in every 500, pushing 100 N down; its
    tangential force is 200 N in the first 4 ms of each stance (a ratio of 2), 40 N after."""
    tr = empty(
        n, 2, 2, 1, 1, q_names=("x", "z"), v_names=("x", "z"), contact_names=("toe",),
        leg_names=("main",), leg_feet=(0,), total_mass=10.0, gravity=9.81, planar=True,
    )  # fmt: skip
    tr.t[:] = np.arange(n) * DT
    phase = (np.arange(n) + 400) % 500
    tr.contact[:, 0] = (phase < 100).astype(np.int8)
    tr.force[:, 0, 2] = np.where(phase < 100, 100.0, 0.0)
    tr.force[:, 0, 0] = np.where(phase < 4, 200.0, np.where(phase < 100, 40.0, 0.0))
    return tr


def rows(metrics: GaitMetrics) -> dict[str, float]:
    return {s.key: s.value for s in metrics.summaries}


def test_the_interior_leaves_out_the_edge_asked_for() -> None:
    tr = slipping_edges_run()
    paper = rows(compute_metrics(tr))  # 10 ms: the touchdown's slip is left out
    assert paper["friction_toe"] == pytest.approx(2.0)
    assert paper["friction_interior_toe"] == pytest.approx(0.4)
    assert paper["friction_first_toe"] == pytest.approx(2.0)
    short = rows(compute_metrics(tr, edge=0.002))  # 2 ms: a small creature's window
    assert short["friction_interior_toe"] == pytest.approx(2.0)
    assert short["friction_first_toe"] == pytest.approx(2.0)
    none = rows(compute_metrics(tr, edge=0.0))
    assert none["friction_interior_toe"] == pytest.approx(2.0)
    assert math.isnan(none["friction_first_toe"])  # nothing in a first 0 ms: n/a


@pytest.mark.parametrize("bad", [-0.001, float("nan"), float("inf")])
def test_the_edge_is_a_time_of_zero_or_more(bad: float) -> None:
    with pytest.raises(MetricsError, match="--friction-edge"):
        compute_metrics(slipping_edges_run(), edge=bad)


def test_legdsl_metrics_reads_the_edge_with_its_unit(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    slipping_edges_run().save(tmp_path)
    assert main(["metrics", str(tmp_path), "--friction-edge", "2ms", "--json"]) == 0
    saved = json.loads(capsys.readouterr().out)
    assert saved["options"]["friction_edge_s"] == pytest.approx(0.002)
    assert main(["metrics", str(tmp_path)]) == 0
    table = capsys.readouterr().out
    assert "past first/last 10 ms" in table  # the paper's, by default
    assert main(["metrics", str(tmp_path), "--friction-edge", "2 ms"]) == 0
    assert "past first/last 2 ms" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("value", "said"),
    [
        ("2kg", "--friction-edge 2kg: --friction-edge is a time (s), but 2kg is a mass (kg)"),
        ("-1ms", "--friction-edge -1ms"),
    ],
)
def test_a_wrong_edge_is_refused_before_anything_is_written(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], value: str, said: str
) -> None:
    slipping_edges_run().save(tmp_path)
    assert main(["metrics", str(tmp_path), "--friction-edge", value]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"legdsl: {said}") and "Traceback" not in err, err
    assert not (tmp_path / "metrics.json").exists()


def test_an_edge_that_leaves_no_interior_says_so(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--friction-edge 10 (10 s: a time without its unit is seconds) left every interior row
    n/a with only the label's '10000 ms' to say why."""
    tr = slipping_edges_run()
    assert compute_metrics(tr).option_notes == {}
    said = compute_metrics(tr, edge=10.0).option_notes["--friction-edge"]
    assert said.startswith("--friction-edge 10 s leaves no sample inside any stance"), said
    assert "the longest contact in the window lasts 0.100 s" in said
    tr.save(tmp_path)
    assert main(["metrics", str(tmp_path), "--friction-edge", "10"]) == 0
    err = capsys.readouterr().err
    assert "legdsl: note: --friction-edge 10 s leaves no sample" in err
    assert "for 10 ms write --friction-edge 10ms" in err
