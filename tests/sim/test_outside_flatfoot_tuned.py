"""The flat-footed biped with its `run` tuned by `legdsl tune` (tests/good/outside/
flatfoot_biped_tuned.leg; docs/biped.md, "A biped on flat feet"): with the shipped biped's
gains flatfoot_biped.leg falls starting from standing at 1.5 m/s (0.70 s: the first stance,
after the drop, never reaches the thrust's end on its toe and stays in THRUST) and at
2.5 m/s (1.78 s); tuned, it starts from standing at both and holds the speed."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import ROOT
from runtime_helpers import needs_c_compiler

from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions

OUTSIDE = ROOT / "tests" / "good" / "outside"

pytestmark = needs_c_compiler


@pytest.fixture(scope="module")
def tuned(tmp_path_factory: pytest.TempPathFactory) -> RunSession:
    generated = tmp_path_factory.mktemp("flatfoot_tuned_generated")
    return RunSession.from_file(OUTSIDE / "flatfoot_biped_tuned.leg", generated=generated)


@pytest.mark.parametrize("speed", [1.5, 2.5])
def test_the_tuned_run_starts_from_standing_and_holds_the_speed(
    tuned: RunSession, speed: float
) -> None:
    opts = RunOptions(duration=7.0)
    run = tuned.run("run", [f"speed={speed}m/s"], options=opts, backend="c").result
    assert run.status == "ok", run.message
    tr = run.trajectory
    assert np.abs(tr.root_rpy[:, :2]).max() < np.radians(15)
    start = int(np.searchsorted(tr.t, 3.0))
    vx = (tr.com[-1, 0] - tr.com[start, 0]) / (tr.t[-1] - tr.t[start])
    assert abs(vx - speed) < 0.04 * speed, vx


def test_with_the_files_full_it_falls_stuck_in_thrust(tuned: RunSession) -> None:
    """What the tune mended: `full` at flatfoot_biped.leg's 0.78 m is not reached on the toe
    after the drop from standing, so the first stance never leaves THRUST, and the tuned
    gains fall too."""
    opts = RunOptions(duration=1.0)
    run = tuned.run("run", ["speed=1.5m/s", "full=0.78m"], options=opts, backend="c").result
    assert run.status != "ok"
    states = [e["state"] for e in run.events if "state" in e]
    assert states[-1] == "THRUST" and "FLIGHT" not in states[1:]
