"""A 3D biped with knees written from the docs (tests/good/outside/knee_biped.leg): ball hips,
a knee hinge whose rotary spring is the leg spring, and the shipped biped's `run` table with the
rests as knee angles. It compiles, runs the same on both backends, keeps its trunk up and level
and runs forward (docs/biped.md, "A biped with knees", has its 5 and 10 s runs)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT
from runtime_helpers import assert_same

from legdsl.pipeline.session import RunSession
from legdsl.sim.c_backend import available
from legdsl.sim.run_loop import RunOptions

LEG = ROOT / "tests" / "good" / "outside" / "knee_biped.leg"

pytestmark = pytest.mark.skipif(
    available() is not None,
    reason=f"the C backend's tests need a C compiler: {available()} (apt-get install gcc)",
)


def test_the_knee_biped_runs_the_same_on_both_backends_and_keeps_its_trunk_up(
    tmp_path: Path,
) -> None:
    sess = RunSession.from_file(LEG, generated=tmp_path)
    opts = RunOptions(duration=1.5)
    python = sess.run("run", ["speed=1m/s"], options=opts, backend="python").result
    c = sess.run("run", ["speed=1m/s"], options=opts, backend="c").result
    assert python.status == "ok", python.message
    assert_same(python, c)
    tr = python.trajectory
    assert tr.root_pos[:, 2].min() > 0.6  # trunk from 0.83 m, runs at 0.64-0.79 m
    assert np.abs(tr.root_rpy[:, :2]).max() < np.radians(8)  # within 3.5 deg in these 1.5 s
    assert 1.0 < tr.com[-1, 0] < 1.5  # running forward from rest towards 1 m/s
