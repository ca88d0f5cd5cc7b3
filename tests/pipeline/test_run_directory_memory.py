"""A run's recording leaves room in memory for writing its directory, a run that cannot
record all its samples is told so before it starts, and a directory being rewritten never
holds an older run's files beside the new run.json. (``legdsl run hopper.leg --scale 1e-30
--time 0.001`` recorded every step until half the memory, then was killed by the system while
writing, leaving a 'incomplete' run.json beside another run's trajectory.npz.)"""

from __future__ import annotations

import json
import tracemalloc
from pathlib import Path

import numpy as np
import pytest
from conftest import CREATURES

import legdsl.pipeline.options
import legdsl.sim.run_loop
from legdsl.pipeline.session import RunSession
from legdsl.sim.recorder import sample_bytes
from legdsl.sim.run_loop import RunOptions
from legdsl.sim.trajectory import Trajectory, empty

HOPPER = CREATURES / "hopper.leg"


def test_writing_a_trajectory_takes_little_memory_beyond_it(tmp_path: Path) -> None:
    traj = empty(20_000, 7, 7, 1, 1, 2)
    rng = np.random.default_rng(1)
    for name in ("q", "v", "force", "com", "com_vel", "kinetic"):  # data that does not deflate
        getattr(traj, name)[...] = rng.random(getattr(traj, name).shape)
    traj.t[:] = np.arange(len(traj)) * 1e-3
    size = len(traj) * traj.row_bytes()
    tracemalloc.start()
    try:
        traj.save(tmp_path)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 0.7 * size, peak / size  # the npz was built whole in memory, and copied
    with np.load(tmp_path / "trajectory.npz") as written:
        assert np.array_equal(written["q"], traj.q)


def test_the_recording_stops_where_growing_it_would_pass_the_budget(
    generated: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    session = RunSession.from_file(HOPPER, generated=generated)
    per = sample_bytes(session.model)
    budget = 3 * 1024 * per - 1  # 2048 rows fit alone, not with the 1024 they are copied from
    monkeypatch.setattr(legdsl.sim.run_loop, "recording_budget", lambda: budget)
    run = session.run("hop", ["speed=1m/s"], options=RunOptions(duration=1e9))
    assert run.status == "interrupted"
    assert len(run.result.trajectory) == 1024


def test_a_run_that_cannot_record_all_its_samples_is_told_before(
    generated: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from legdsl.pipeline.options import recording_note

    model = RunSession.from_file(HOPPER, generated=generated).model
    per = sample_bytes(model)
    monkeypatch.setattr(legdsl.pipeline.options, "recording_budget", lambda: 6 * 1024 * per)
    assert recording_note(RunOptions(duration=5.0), model) is None  # 962 samples
    note = recording_note(RunOptions(duration=1e9, record_rate=0.0), model)
    assert note is not None
    assert "will stop as interrupted (exit 130) near t = " in note
    assert "with 4096 samples" in note  # 1024 -> 2048 -> 4096 (8192 with 4096: past it)
    assert note.endswith("(a lower --record-rate, or a shorter --time)")
    said = recording_note(RunOptions(duration=1e9, record_rate=0.0), model, flags=False)
    assert said is not None and "(exit 130)" not in said and "--" not in said  # the API's
    assert said.endswith("(a lower record_rate=, or a shorter time=)")


def test_an_older_runs_files_are_gone_once_the_new_run_json_is_written(
    generated: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    session = RunSession.from_file(HOPPER, generated=generated)
    out = tmp_path / "x"
    session.run("hop", ["speed=1m/s"], options=RunOptions(duration=0.2)).write(out)
    assert (out / "trajectory.npz").is_file()

    def killed(self: Trajectory, directory: Path) -> None:
        raise KeyboardInterrupt  # the system's kill, as far as the directory can tell

    monkeypatch.setattr(Trajectory, "save", killed)
    run = session.run("hop", ["speed=1m/s"], options=RunOptions(duration=0.3))
    with pytest.raises(KeyboardInterrupt):
        run.write(out)
    assert json.loads((out / "run.json").read_text())["status"] == "incomplete"
    assert sorted(p.name for p in out.iterdir()) == ["run.json"]
