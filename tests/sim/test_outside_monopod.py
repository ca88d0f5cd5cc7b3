"""Raibert's 3D one-legged hopper written from the docs (tests/good/outside/monopod_3d.leg): a
body on one telescoping leg with a gimbal hip, no static stability. It hops in place, runs at
1 and 2 m/s along x, and sideways at a commanded speed (``trim_step_side_to``), the same on
both backends."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import ROOT
from runtime_helpers import assert_same, needs_c_compiler

from legdsl.check.source import check_model
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions

LEG = ROOT / "tests" / "good" / "outside" / "monopod_3d.leg"

pytestmark = needs_c_compiler


@pytest.fixture(scope="module")
def session(tmp_path_factory: pytest.TempPathFactory) -> RunSession:
    """One generated tree for the module: the creature is compiled once."""
    return RunSession.from_file(LEG, generated=tmp_path_factory.mktemp("monopod_generated"))


def _mean_velocity(session: RunSession, settings: list[str]) -> np.ndarray:
    """Ten seconds in C; the centre of mass's mean horizontal velocity from 3 s."""
    run = session.run("hop", settings, options=RunOptions(duration=10.0), backend="c").result
    assert run.status == "ok", run.message
    tr = run.trajectory
    assert tr.root_pos[:, 2].min() > 0.4  # the body stays up (it starts at 0.72 m)
    assert np.abs(tr.root_rpy[:, :2]).max() < np.radians(15)
    start = int(np.searchsorted(tr.t, 3.0))
    return (tr.com[-1, :2] - tr.com[start, :2]) / (tr.t[-1] - tr.t[start])


def test_the_monopod_checks_clean() -> None:
    model = check_model(LEG)
    assert model.name == "monopod_3d" and len(model.legs) == 1


def test_it_hops_in_place_for_10_s(session: RunSession) -> None:
    velocity = _mean_velocity(session, [])
    assert np.abs(velocity).max() < 0.01


@pytest.mark.parametrize("speed", [1.0, 2.0])
def test_it_runs_along_x_within_5_percent(session: RunSession, speed: float) -> None:
    vx, vy = _mean_velocity(session, [f"speed={speed}m/s"])
    assert abs(vx - speed) < 0.05 * speed and abs(vy) < 0.01


def test_its_sideways_trim_holds_a_sideways_command(session: RunSession) -> None:
    """trim_step_side_to trims towards 0.5 m/s sideways (0.504 m/s); eq. (3) alone reached
    0.41 m/s, and trim_step_side (towards 0) would fight the command."""
    vx, vy = _mean_velocity(session, ["side_speed=0.5m/s"])
    assert abs(vx) < 0.01 and abs(vy - 0.5) < 0.025


def test_the_run_is_the_same_on_both_backends(session: RunSession) -> None:
    opts = RunOptions(duration=2.0)
    settings = ["speed=1m/s", "side_speed=0.5m/s"]
    python = session.run("hop", settings, options=opts, backend="python").result
    c = session.run("hop", settings, options=opts, backend="c").result
    assert python.status == "ok", python.message
    assert_same(python, c)
