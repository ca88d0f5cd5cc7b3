"""A run told diverged after it ran on (an energy rise without a source) diverged at its
``diverged_at``, as ``legdsl run`` says it; animate and export-motion said its later
``ended_at`` (0.352 s where the run said 0.3432 s), as plot and metrics did before them."""

from __future__ import annotations

import json
from pathlib import Path

from conftest import CREATURES

from legdsl.export.motion import load_motion
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions


def test_animate_and_export_motion_say_the_time_the_run_diverged(
    tmp_path: Path, generated: Path
) -> None:
    session = RunSession.from_file(CREATURES / "hopper.leg", generated=generated)
    session.run("hop", ["speed=1m/s"], options=RunOptions(duration=0.4)).write(tmp_path)
    info = json.loads((tmp_path / "run.json").read_text())
    ran_on = {"status": "diverged", "ended_at": 0.352, "diverged_at": 0.3432,
              "cause": "the total energy rose from 1 J to 5e4 J"}  # fmt: skip
    (tmp_path / "run.json").write_text(json.dumps(info | ran_on))
    motion = load_motion(tmp_path, generated=generated)
    assert motion.ended_at == 0.3432
    fell = {"status": "fell", "ended_at": 0.352, "cause": "the root tilted 61 deg"}
    (tmp_path / "run.json").write_text(json.dumps(info | fell))
    assert load_motion(tmp_path, generated=generated).ended_at == 0.352
