"""Under ``ulimit -v`` the note before a run that cannot record all its samples named its
recording's memory as the budget before the run ("may take 937 MB of memory (half of what
the run may use)"), while the run, stopping, named the budget it stopped at, with its
recording in memory ("half of the memory the run may take (0.705 GiB)"): two figures in two
units for one limit. The note now tells the run's figure at its stop, in GiB. The address
space is simulated: what the limit leaves is a fixed amount less the recording held."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest
from conftest import CREATURES

import legdsl.pipeline.options as options
import legdsl.sim.recorder as recorder
from legdsl.cli import main
from legdsl.pipeline.session import RunSession
from legdsl.sim.recorder import sample_bytes
from legdsl.sim.trajectory import Trajectory

HOPPER = str(CREATURES / "hopper.leg")


def test_the_note_names_the_figure_the_run_stops_at(
    generated: Path,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    per = sample_bytes(RunSession.from_file(CREATURES / "hopper.leg", generated=generated).model)
    limit = 20_000 * per  # 2048 -> 4096 rows fit beside the 2048 held, 8192 not beside 4096
    held = [0]  # the recording in memory: none before the run, then as it grows
    grown = Trajectory.grown

    def growing(self: Trajectory, capacity: int) -> Any:
        new = grown(self, capacity)
        held[0] = capacity * per
        return new

    monkeypatch.setattr(Trajectory, "grown", growing)
    left = lambda: limit - held[0]  # noqa: E731
    monkeypatch.setattr(recorder, "address_space_left", left)
    monkeypatch.setattr(options, "address_space_left", left, raising=False)
    argv = ["run", HOPPER, "--controller", "hop", "--time", "1e9", "--record-rate", "0",
            "--backend", "python", "--generated", str(generated), "--out", str(tmp_path / "r")]  # fmt: skip
    assert main(argv) == 130
    captured = capsys.readouterr()
    said = captured.err + captured.out
    note = re.search(r"note: this run would record .*? with (\d+) samples, its recording "
                     r"filling half of the memory the run may take \(about ([0-9.]+) GiB", said)  # fmt: skip
    stop = re.search(r"interrupted by its recording filling half of the memory the run may "
                     r"take \(([0-9.]+) GiB", said)  # fmt: skip
    assert note is not None and stop is not None, said
    assert note.group(1) == "4096" and note.group(2) == stop.group(1), said
    assert float(stop.group(1)) == pytest.approx((limit - 4096 * per) / 2 / 2**30, rel=1e-2)
