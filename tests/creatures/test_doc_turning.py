"""docs/quadruped.md's trot on the 8 m square (the Turning table's row, run with the path its
command gives) and the bound outside its searched speeds ("Outside the range: ...") come out
as written, on the C backend. The runs are chaotic at the bit level: when one moves, re-measure
it with the doc's command and update the doc."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from doc_tables import Comparison, Row, fell_at, heading_speed, numbers, run_creature, table
from runtime_helpers import needs_c_compiler

import legdsl
from legdsl.pipeline.session import Run

pytestmark = needs_c_compiler

ROOT = Path(__file__).resolve().parents[2]
DOC = (ROOT / "docs" / "quadruped.md").read_text(encoding="utf-8")
TURNING = table("docs/quadruped.md", "| run | outcome | lateral deviation RMS (max) from 3 s |")


def test_the_trot_on_the_square(generated: Path) -> None:
    (row,) = [r for r in TURNING if r["run"].startswith("8 m square")]
    command = re.search(r'--time (\d+) \\\n\s+--path "(square\([^"]*\))" --out runs/q_square', DOC)
    assert command, "docs/quadruped.md, Turning: the square's command moved"
    seconds, square = float(command[1]), command[2]
    look = re.search(r"lookahead = [\d.]+ m", square)
    assert look is None or look[0] in row["run"], "the row should name the path's look-ahead"
    run = legdsl.load(ROOT / "creatures" / "quadruped.leg", generated=generated).run(
        controller="trot", set={"speed": "1.5 m/s"}, time=seconds, path=square
    )
    assert run.status == "ok", run.info.get("message")
    (report,) = run.info["path_reports"]
    check = Comparison(f"legdsl run creatures/quadruped.leg --controller trot --set "
                       f"speed=1.5m/s --time {seconds:g} --path '{square}'")  # fmt: skip
    check.figures(row, "outcome", [report["laps"]], numbers(row["outcome"]))
    lateral = "lateral deviation RMS (max) from 3 s"
    check.figures(row, lateral, [report["lateral_rms"], report["lateral_max"]],
                  numbers(row[lateral]))  # fmt: skip
    check.number(row, "speed along the path", report["path_speed"])
    check.check()


OUTSIDE = re.search(
    r"Outside the range:\s+1\.5 m/s now holds \((\d+) s, ([-+\u2212][\d.]+)%, its windows\s+"
    r"([-+\u2212][\d.]+) to\s+([-+\u2212][\d.]+)%;[^)]*\), and so does\s+3\.7 m/s \((\d+) s,\s+"
    r"([-+\u2212][\d.]+)%, its windows\s+([-+\u2212][\d.]+) to\s+([-+\u2212][\d.]+)%",
    DOC,
)


def _windows(run: Run, command: float) -> list[float]:
    """The relative error (%) of the centre of mass's mean speed along x over each 3 s window
    from 3 s, every 0.5 s (docs/quadruped.md, "The bound's speed over 3 s windows")."""
    tr = run.result.trajectory
    t, x = tr.t, tr.com[:, 0]

    def mean(a: float, b: float) -> float:
        i, j = np.searchsorted(t, a), min(np.searchsorted(t, b), len(t) - 1)
        return float((x[j] - x[i]) / (t[j] - t[i]))

    starts = np.arange(3.0, t[-1] - 3.0 + 1e-9, 0.5)
    return [100 * (mean(a, a + 3.0) / command - 1) for a in starts]


@pytest.mark.parametrize("speed", [1.5, 3.7])
def test_the_bound_outside_its_range(generated: Path, speed: float) -> None:
    assert OUTSIDE, "docs/quadruped.md, The bound: the 'Outside the range' sentence moved"
    seconds, error, low, high = OUTSIDE.groups()[:4] if speed == 1.5 else OUTSIDE.groups()[4:]
    run = run_creature(generated, "quadruped", "bound", [f"speed={speed:g}m/s"], float(seconds))
    row = Row("docs/quadruped.md", DOC[: OUTSIDE.start()].count("\n") + 1, {})
    check = Comparison(f"legdsl run creatures/quadruped.leg --controller bound --set "
                       f"speed={speed:g}m/s --time {seconds}")  # fmt: skip
    assert fell_at(run) is None, f"the bound fell at {fell_at(run)} s at {speed} m/s"
    windows = _windows(run, speed)
    check.figures(
        row, f"{speed} m/s: windows", [min(windows), max(windows)], numbers(f"{low} {high}")
    )
    mean = heading_speed(run, 3.0)  # the table's "mean speed from 3 s"
    check.figures(row, f"{speed} m/s: error", [100 * (mean / speed - 1)], numbers(error))
    check.check()
