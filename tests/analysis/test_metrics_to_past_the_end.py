"""legdsl metrics RUN --to 10 of a 2.995 s run said 'gait metrics from 0.000 s to 10.000 s',
while --from 5 was refused; --to past the end now measures to the run's end, which the
header says, with a note."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.cli import main
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions


def test_a_window_past_the_end_is_measured_to_the_end(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    session = RunSession.from_file(CREATURES / "hopper.leg", generated=generated)
    out = tmp_path / "h"
    session.run("hop", ["speed=1m/s"], options=RunOptions(duration=1.3)).write(out)
    capsys.readouterr()
    assert main(["metrics", str(out), "--to", "10", "--generated", str(generated)]) == 0
    captured = capsys.readouterr()
    assert "gait metrics from 0.000 s to 1.300 s" in captured.out
    assert (
        "legdsl: note: --to 10s is after the run's end: measured to its end, 1.300 s"
        in captured.err
    )
