"""The biped with knees made to run 2 m/s (tests/good/outside/knee_biped_fast.leg; docs/biped.md,
"A biped with knees"). knee_biped_tuned.leg falls at 2 m/s (0.98 s): its landing leg unfolds to
full length 36 ms after liftoff, low in a flight that clears that length by about a centimetre,
and brushes the ground; the table, which only waits for each row's event in turn, runs the brush
through LOADING to FLIGHT in 20 ms and swaps the roles back, so one leg takes two stances. The
fast file unfolds the landing leg as the body falls, needs the foot down for COMPRESSION and
THRUST, ends thrust at the length of the spring's current rest, and was tuned over 1 to 2 m/s;
tuned for speed alone (balance near 0) its trunk pitched 13.5 deg each stride at 2 m/s, and tuned
again with --pitch-weight (balance 8) it pitches under 2 deg."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from conftest import ROOT
from runtime_helpers import needs_c_compiler

from legdsl.analysis.metrics import compute_metrics
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions

OUTSIDE = ROOT / "tests" / "good" / "outside"

pytestmark = needs_c_compiler


def stances(events: list[dict[str, Any]]) -> list[tuple[float, float]]:
    """(time of entering LOADING, how long until FLIGHT) for each stance of the table."""
    out = []
    loading = None
    for e in events:
        if e.get("state") == "LOADING":
            loading = e["t"]
        elif e.get("state") == "FLIGHT" and loading is not None:
            out.append((loading, e["t"] - loading))
            loading = None
    return out


@pytest.fixture(scope="module")
def fast(tmp_path_factory: pytest.TempPathFactory) -> RunSession:
    generated = tmp_path_factory.mktemp("knee_fast_generated")
    return RunSession.from_file(OUTSIDE / "knee_biped_fast.leg", generated=generated)


def test_it_starts_from_standing_at_2_m_s_and_holds_the_speed(fast: RunSession) -> None:
    run = fast.run("run", ["speed=2m/s"], options=RunOptions(duration=5.0), backend="c").result
    assert run.status == "ok", run.message
    tr = run.trajectory
    assert np.abs(tr.root_rpy[:, :2]).max() < np.radians(20)
    start = int(np.searchsorted(tr.t, 3.0))
    vx = (tr.com[-1, 0] - tr.com[start, 0]) / (tr.t[-1] - tr.t[start])
    assert abs(vx - 2.0) < 0.05 * 2.0, vx
    # the trunk's stride pitch magnitude: 13.5 deg before the tune with --pitch-weight
    pitch = compute_metrics(tr, t_from=3.0).value("pitch_magnitude")
    assert pitch < 4.0, pitch
    # Every stance is a real one (the brushes lasted 20 ms), and the feet alternate.
    assert min(d for _, d in stances(run.events)) > 0.1
    feet = [e["contact"] for e in run.events if e["kind"] == "touchdown"]
    assert all(a != b for a, b in zip(feet, feet[1:], strict=False)), feet


def test_the_tuned_file_brushes_the_ground_and_falls_at_2_m_s(tmp_path: Any) -> None:
    """The cause, on knee_biped_tuned.leg: a stance of under 40 ms (a brush) before the fall."""
    session = RunSession.from_file(OUTSIDE / "knee_biped_tuned.leg", generated=tmp_path)
    run = session.run("run", ["speed=2m/s"], options=RunOptions(duration=2.0), backend="c").result
    assert run.status != "ok"
    brushes = [t for t, d in stances(run.events) if d < 0.04]
    assert brushes and brushes[0] < run.sim_time, stances(run.events)
