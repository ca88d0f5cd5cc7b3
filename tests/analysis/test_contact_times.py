"""The touchdown spreads and the support phases are timed by run.json's events (exact to the
step), not by the samples: at the default 200 Hz a 7.2 ms lag between two feet read as two
record intervals, 10.4 ms, out of "unison" (10 ms), and a gallop's 4.4 ms lead as 5.2 ms."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from legdsl.analysis.metrics import compute_metrics
from legdsl.cli import main
from legdsl.sim.trajectory import Trajectory, empty

INTERVAL = 0.0052  # s: the default record interval (200 Hz, on a 0.4 ms step)
STRIDE = 0.4  # s
LAG = 0.0072  # s: the second foot lands (and lifts) this long after the first
STANCE = 0.1  # s


def _landings(n_strides: int = 10) -> tuple[Trajectory, list[dict[str, Any]]]:
    """Two legs, each stride: l down for STANCE, r the same LAG later. The first touchdown of
    each stride falls just before a sample, so the second's first sample is two intervals on."""
    events: list[dict[str, Any]] = []
    for k in range(n_strides):
        first = round((8 + 77 * k) * INTERVAL - 0.0001, 6)
        for contact, at in (("toe_l", first), ("toe_r", first + LAG)):
            events.append({"t": at, "kind": "touchdown", "contact": contact})
            events.append({"t": at + STANCE, "kind": "liftoff", "contact": contact})
    n = int(n_strides * 77 + 40)
    names = ("x", "z")
    tr = empty(n, 2, 2, 2, 2, q_names=names, v_names=names, contact_names=("toe_l", "toe_r"),
               leg_names=("l", "r"), leg_feet=(0, 1), total_mass=10.0, gravity=9.81,
               planar=True)  # fmt: skip
    tr.t[:] = np.arange(n) * INTERVAL
    for c, contact in enumerate(("toe_l", "toe_r")):  # the flags the recorder samples
        own = [e for e in events if e["contact"] == contact]
        for down, up in zip(own[::2], own[1::2], strict=True):
            tr.contact[(tr.t >= down["t"]) & (tr.t < up["t"]), c] = 1
    tr.speed_command[:] = 1.0
    return tr, events


def test_a_pair_7_ms_apart_is_in_unison_though_its_samples_are_10_ms_apart() -> None:
    tr, events = _landings()
    on_samples = compute_metrics(tr, groups={"pair": ["l", "r"]})
    assert on_samples.value("touchdown_spread_pair") == pytest.approx(2 * INTERVAL)  # as before
    m = compute_metrics(tr, groups={"pair": ["l", "r"]}, events=events)
    assert m.value("touchdown_spread_pair") == pytest.approx(LAG)
    assert m.value("unison_pair") == 1.0 and m.summary("unison_pair").n == 10


def test_the_support_phases_are_timed_by_the_events() -> None:
    tr, events = _landings()
    m = compute_metrics(tr, events=events)
    assert m.value("single_support_duration_l") == pytest.approx(LAG)
    assert m.value("single_support_duration_r") == pytest.approx(LAG)
    assert m.value("double_support_duration") == pytest.approx(STANCE - LAG)


def test_legdsl_metrics_reads_the_events_of_run_json(tmp_path: Path) -> None:
    tr, events = _landings()
    tr.save(tmp_path)
    (tmp_path / "run.json").write_text(json.dumps({"status": "ok", "events": events}))
    assert main(["metrics", str(tmp_path), "--group", "pair=l,r"]) == 0
    rows = json.loads((tmp_path / "metrics.json").read_text())["summary"]
    assert rows["touchdown_spread_pair"]["value"] == pytest.approx(LAG)
    assert rows["unison_pair"]["value"] == 1.0
