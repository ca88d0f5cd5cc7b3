"""The body's margin to the terrain in ``legdsl metrics`` (legdsl.pipeline.terrain_rows)."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.lang.errors import UsageError
from legdsl.pipeline.measure import measure_run
from legdsl.pipeline.session import RunSession
from legdsl.sim.run_loop import RunOptions


def test_a_window_without_samples_names_no_body_and_no_time(
    generated: Path, tmp_path: Path
) -> None:
    """The row's label said ', ' and 'at nan s' (no body, no time) for a window no sample is in;
    such a window is now refused, saying how far apart the samples are."""
    text = (CREATURES / "hopper.leg").read_text()
    text = text.replace(
        "friction none\n  }", "friction none\n    terrain step(x = 3 m, height = 5 cm)\n  }"
    )
    source = tmp_path / "hopper.leg"
    source.write_text(text)
    session = RunSession.from_file(source, generated=generated)
    session.run("hop", options=RunOptions(duration=0.2), backend="python").write(tmp_path / "run")
    between = r"none lies from 0.1011 to 0.1012 s; widen the window: the run was recorded every"
    with pytest.raises(UsageError, match=between):
        measure_run(tmp_path / "run", 0.1011, 0.1012, generated=generated)
    metrics, _ = measure_run(tmp_path / "run", generated=generated)
    (row,) = [s for s in metrics.summaries if s.key.startswith("terrain_margin_")]
    assert row.label.startswith("least margin of the body to the step at x = 3 m, body at 0")
