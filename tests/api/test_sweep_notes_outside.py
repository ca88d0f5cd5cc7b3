"""A sweep's rows once in: values too large for a heat map's axis (an outside user's
`--grid k_trim=1e308:1.7e308:2` was 'internal error (ValueError: arange: cannot compute
length)', exit 70, no picture), and swept values that changed nothing (`--grid
stroke=2cm,3cm,45mm`: bit-identical rows, no note, where legdsl tune says so of its
parameters)."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import pytest

from legdsl.api.sweep_notes import beyond_a_plot, changed_nothing
from legdsl.cli import main

ROOT = Path(__file__).resolve().parents[2]
HOPPER = ROOT / "creatures" / "hopper.leg"


def sweep(tmp_path: Path, *given: str) -> int:
    return main(["sweep", str(HOPPER), "--controller", "hop", *given, "--time", "0.3",
                 "--from", "0.1", "--jobs", "1", "--out", str(tmp_path / "out"),
                 "--generated", str(tmp_path / "generated")])  # fmt: skip


@pytest.mark.usefixtures("hopper_modules")
def test_values_too_large_for_a_plot_keep_the_rows_and_say_why_there_is_no_picture(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert sweep(tmp_path, "--grid", "k_trim=1e308:1.7e308:2") == 0
    err = capsys.readouterr().err
    assert "internal error" not in err
    assert "sweep.png not drawn: its swept k_trim reaches 1.7e+308" in err
    with (tmp_path / "out" / "sweep.csv").open() as f:
        assert len(list(csv.DictReader(f))) == 2
    assert not (tmp_path / "out" / "sweep.png").exists()


def test_too_large_is_said_of_swept_and_measured_values() -> None:
    rows = [{"k": 1.0, "speed_error": 2e305}, {"k": 2.0, "speed_error": math.nan}]
    said = beyond_a_plot(rows, ["k"], "speed_error")
    assert said is not None and "measured speed_error reaches 2e+305" in said
    assert beyond_a_plot([{"k": 1e299, "speed_error": 1.0}], ["k"], "speed_error") is None


def test_a_name_that_changed_nothing_is_found_among_rows_differing_in_it_alone() -> None:
    def row(speed: float, stroke: float, error: float) -> dict[str, object]:
        return {"speed": speed, "stroke": stroke, "outcome": "ok", "simulated": 1.0,
                "strides": 3, "speed_error": error}  # fmt: skip

    rows = [row(s, k, s / 10) for s in (0.5, 1.0) for k in (0.02, 0.03)]
    assert changed_nothing(rows, ["speed", "stroke"], ["speed_error"]) == ["stroke"]
    rows[1]["speed_error"] = 0.051  # stroke changed one row
    assert changed_nothing(rows, ["speed", "stroke"], ["speed_error"]) == []
    fell = [{**r, "outcome": "fell at 0.100 s"} for r in rows[:2]]  # all fell alike: unsaid
    assert changed_nothing(fell, ["stroke"], ["speed_error"]) == []


@pytest.mark.usefixtures("hopper_modules")
def test_a_sweep_says_when_its_values_changed_nothing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert sweep(tmp_path, "--grid", "max_step=1:2:2") == 0
    err = capsys.readouterr().err
    assert "note: --grid max_step: its values changed nothing in these runs" in err
