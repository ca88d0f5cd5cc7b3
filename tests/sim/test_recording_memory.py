"""A recording that the process's memory limit (``ulimit -v``) cannot hold: the run stops as
interrupted, keeping what it recorded, and its directory is written whole. Under ``ulimit -v
700000`` a run of ``--time 1e9 --record-rate 0`` grew its recording until Python's MemoryError
(exit 2, nothing written), and then the CSV, built whole in memory, failed too."""

from __future__ import annotations

import resource
from pathlib import Path

import pytest
from conftest import CREATURES

import legdsl.sim.run_loop
from legdsl.pipeline.session import RunSession
from legdsl.sim.recorder import recording_budget
from legdsl.sim.run_loop import RunOptions
from legdsl.sim.trajectory import Trajectory


def test_the_budget_is_half_of_what_the_address_space_limit_leaves(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    unlimited = recording_budget()
    assert unlimited is not None and unlimited > 0
    taken = int(Path("/proc/self/statm").read_text().split()[0]) * resource.getpagesize()
    limit = taken + 64 * 2**20
    real = resource.getrlimit

    def limited(kind: int) -> tuple[int, int]:
        return (limit, real(kind)[1]) if kind == resource.RLIMIT_AS else real(kind)

    monkeypatch.setattr(resource, "getrlimit", limited)
    budget = recording_budget()
    assert budget is not None and budget <= 32 * 2**20 and budget < unlimited


@pytest.mark.parametrize("backend", ["python", "c"])
def test_memory_refused_as_the_recording_grows_ends_the_run_keeping_it(
    backend: str, generated: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    grown = Trajectory.grown

    def refused(self: Trajectory, rows: int) -> Trajectory:
        if rows > 2048:
            raise MemoryError
        return grown(self, rows)

    monkeypatch.setattr(Trajectory, "grown", refused)
    monkeypatch.setattr(legdsl.sim.run_loop, "recording_budget", lambda: None)
    session = RunSession.from_file(CREATURES / "hopper.leg", generated=generated)
    run = session.run("hop", ["speed=1m/s"], options=RunOptions(duration=1e9), backend=backend)
    assert run.status == "interrupted"
    assert "its recording filling half of the memory the run may take" in run.result.message
    assert len(run.result.trajectory) == 2048
    run.write(tmp_path / "run")
    rows = (tmp_path / "run" / "trajectory.csv").read_text().count("\n")
    assert rows == 2049  # the header and every sample
