"""The waits of the segment and path reports follow the creature's size: a quadruped scaled by
4 was still ramping up 3 s after a takeover (-11.9% where the same gait holds -0.6%), and at
1/4 every segment was 'too short to measure'. run.json's ``time_unit`` (the creature's natural
time over a 0.81 m one's, Table 1's sqrt(L)) scales them."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from legdsl.lang.errors import UsageError
from legdsl.pipeline.measure import run_segments
from legdsl.sim.trajectory import Trajectory, empty


def _ramping(tmp_path: Path, unit: object) -> Path:
    """A 12 s run at 100 Hz of a creature twice the reference's time: switched at 4 s, each
    controller ramps for 5 s (to 6 s of its time it is 2 m/s short) then holds its command."""
    n = 1201
    tr: Trajectory = empty(n, 1, 1, 1, 0, q_names=("x",), v_names=("x",), contact_names=("toe",))
    tr.t[:] = np.arange(n) * 0.01
    since = np.where(tr.t < 4, tr.t, tr.t - 4)
    tr.speed_command[:] = np.where(tr.t < 4, 2.0, 4.0)
    tr.com_vel[:, 0] = np.where(since < 5, tr.speed_command - 2.0, tr.speed_command)
    tr.save(tmp_path)
    segments = [{"controller": "trot", "from": 0.0, "to": 4.0},
                {"controller": "bound", "from": 4.0, "to": 12.0}]  # fmt: skip
    (tmp_path / "run.json").write_text(json.dumps({"segments": segments, "time_unit": unit}))
    return tmp_path


def test_the_segments_settle_for_the_creatures_time(tmp_path: Path) -> None:
    first, second = run_segments(_ramping(tmp_path, 2.0))
    assert (first["settle"], first["shortest"]) == (6.0, 2.0)
    assert first["speed"] is None  # 4 s: under its 6 s of settling, nothing to measure
    assert second["measured_from"] == 10.0
    assert second["speed"] == pytest.approx(4.0) and second["error_percent"] == pytest.approx(0)


def test_a_run_recorded_without_a_time_unit_settles_3_s_and_a_damaged_one_is_refused(
    tmp_path: Path,
) -> None:
    run = _ramping(tmp_path, 1.0)
    info = json.loads((run / "run.json").read_text())
    del info["time_unit"]
    (run / "run.json").write_text(json.dumps(info))
    assert run_segments(run)[1]["measured_from"] == 7.0
    with pytest.raises(UsageError, match="'time_unit' is not a positive number"):
        run_segments(_ramping(tmp_path, -1))
