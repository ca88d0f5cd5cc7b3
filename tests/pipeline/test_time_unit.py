"""run.json's ``time_unit``: the creature's natural time over a 0.81 m one's, by which the path
report's 3 s after the start (and the segments' waits) scale; a ``--scale L`` run's is the
scaled creature's, sqrt(L) times its own."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from conftest import CREATURES

from legdsl.cli import main
from legdsl.pipeline.measure import measure_run

BIPED_HEIGHT = 0.83  # m: the biped's root over its feet at the start (docs/scaling.md)


def test_a_scaled_runs_path_report_starts_after_its_creatures_settling_time(
    generated: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "run"
    shape = "circle(center = (0, 10) m, radius = 10 m, turn = left)"
    args = ["run", str(CREATURES / "biped.leg"), "--controller", "run", "--path", shape,
            "--time", "0.3", "--scale", "4", "--generated", str(generated),
            "--backend", "python", "--out", str(out)]  # fmt: skip
    assert main(args) == 0
    assert "lateral deviation RMS (from 6.1 s)" in capsys.readouterr().out
    info = json.loads((out / "run.json").read_text())
    unit = math.sqrt(BIPED_HEIGHT / 0.81) * 2
    assert info["time_unit"] == pytest.approx(unit, rel=1e-6)
    (at_run,) = info["path_reports"]
    _, (measured,) = measure_run(out, generated=generated)
    assert at_run["from"] == measured["from"] == 6.1  # 3 s x 2.024, to two figures
